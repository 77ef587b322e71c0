#include "backend/cpu/solver_stages.hpp"

#include <algorithm>
#include <cmath>

#include "backend/boundary.hpp"
#include "backend/reference/equations.hpp"

namespace pbf::stages {
using boundary::clampToBox;

void predictPositions(const Vec3& gravity, float dt, const Aabb& box, const Float3Array& position,
                      Float3Array& velocity, Float3Array& predicted, std::size_t begin,
                      std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
        const Vec3 v = velocity.get(i) + dt * gravity;
        velocity.set(i, v);
        predicted.set(i, clampToBox(box, position.get(i) + dt * v));
    }
}

void warmStartPredictions(const SolverConstants& c, float warm, float dt,
                          const Float3Array& solveAcceleration, const float* lastDensity,
                          Float3Array& predicted, std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
        predicted.set(i,
                      clampToBox(c.collisionBox,
                                 reference::warmStart(c, predicted.get(i), solveAcceleration.get(i),
                                                      lastDensity[i], warm, dt)));
}

void recordSolveAcceleration(float dt, const Float3Array& position, const Float3Array& predicted,
                             const Float3Array& velocity, Float3Array& solveAcceleration,
                             std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
        solveAcceleration.set(i, reference::solveAcceleration(position.get(i), predicted.get(i),
                                                              velocity.get(i), dt));
}

// The neighbour loops below run on full SIMD vectors of neighbours
// (simd.hpp): gather x_j, mask the lanes past the list's end and those
// outside the kernel's support, accumulate per lane, one tree sum at the end.
// Constant factors (the kernels' coefficients) are applied once per particle.

void packPositions(const Float3Array& predicted, PackedPoint* packed, std::size_t begin,
                   std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
        packed[i] = {predicted.x[i], predicted.y[i], predicted.z[i], 0.0f};
}

void unpackPositions(const PackedPoint* packed, Float3Array& predicted, std::size_t begin,
                     std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
        predicted.set(i, {packed[i].x, packed[i].y, packed[i].z});
}

void packPositionDensities(const PackedPoint* predicted, const float* density,
                           PackedPoint* positionDensity, std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
        positionDensity[i] = {predicted[i].x, predicted[i].y, predicted[i].z, density[i]};
}

void updateVelocity(float inverseDt, const Float3Array& position, const Float3Array& predicted,
                    const float* density, Float3Array& velocity, PackedPoint* velocityDensity,
                    std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
        const Vec3 v = (predicted.get(i) - position.get(i)) * inverseDt;
        velocity.set(i, v);
        velocityDensity[i] = {v.x, v.y, v.z, density[i]};
    }
}

void applyVorticityConfinement(const SolverConstants& c, float vorticityEpsilon, float dt,
                               const NeighborSearch& search, const Float3Array& predicted,
                               const Float3Array& vorticity, const float* density,
                               Float3Array& velocity, std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
        Vec3 v = velocity.get(i);
        {
            const Vec3 xi = predicted.get(i);
            const Vec3 omegaI = vorticity.get(i);
            const float magnitudeI = length(omegaI);
            Vec3 eta{};  // gradient of |omega| (SPH difference form)
            const NeighborList nbrs = search.neighbors(i);
            for (std::size_t k = 0; k < nbrs.size(); ++k) {
                const std::uint32_t j = nbrs[k];
                const Vec3 rij = xi - predicted.get(j);
                const float r = length(rij);
                const float volumeJ = c.particleMass / density[j];
                eta +=
                    c.spiky.gradient(rij, r) * ((length(vorticity.get(j)) - magnitudeI) * volumeJ);
            }
            const float etaLength = length(eta);
            if (etaLength > 1e-20f) {
                const Vec3 normal = eta * (1.0f / etaLength);
                v += cross(normal, omegaI) * (dt * vorticityEpsilon * c.h * magnitudeI);
            }
        }
        velocity.set(i, v);
    }
}

void applyPhysicalViscosity(const SolverConstants& c, float nu, float dt,
                            const NeighborSearch& search, const PackedPoint* predicted,
                            const PackedPoint* velocityDensity, Float3Array& velocity,
                            std::size_t begin, std::size_t end) {
    const auto position = [&](std::uint32_t j) {
        return Vec3{predicted[j].x, predicted[j].y, predicted[j].z};
    };
    const auto speed = [&](std::uint32_t j) {
        return Vec3{velocityDensity[j].x, velocityDensity[j].y, velocityDensity[j].z};
    };
    for (std::size_t i = begin; i < end; ++i) {
        const std::uint32_t self = std::uint32_t(i);
        const Vec3 xi = position(self), vi = speed(self);
        const float rhoI = velocityDensity[i].w;
        const NeighborList nbrs = search.neighbors(i);
        Vec3 a{};
        float moment = 0.0f;
        for (std::size_t k = 0; k < nbrs.size(); ++k) {
            const std::uint32_t j = nbrs[k];
            const Vec3 rij = xi - position(j);
            const float rhoJ = velocityDensity[j].w;
            a += reference::viscosityTerm(c, nu, rij, vi, speed(j), rhoI, rhoJ);
            moment += reference::viscosityMomentTerm(c, rij, rhoI, rhoJ);
        }
        for (int axis = 0; axis < 3; ++axis)
            for (const int side : {-1, 1}) {
                if (!reference::wallInReach(c, xi, axis, side)) continue;
                const float plane = reference::wallPlane(c, axis, side);
                const Vec3 image = xi - reference::mirrored(xi, axis, plane);
                a += reference::viscosityTerm(c, nu, image, vi,
                                              reference::mirroredVelocity(vi, axis), rhoI, rhoI);
                moment += reference::viscosityMomentTerm(c, image, rhoI, rhoI);
                for (std::size_t k = 0; k < nbrs.size(); ++k) {
                    const std::uint32_t j = nbrs[k];
                    const Vec3 rij = xi - reference::mirrored(position(j), axis, plane);
                    const float rhoJ = velocityDensity[j].w;
                    a += reference::viscosityTerm(
                        c, nu, rij, vi, reference::mirroredVelocity(speed(j), axis), rhoI, rhoJ);
                    moment += reference::viscosityMomentTerm(c, rij, rhoI, rhoJ);
                }
            }
        a = reference::normalisedViscosity(a, moment);
        velocity.set(i, velocity.get(i) + a * dt);
    }
}

void resolveSolidCollisions(const SolverConstants& c, const SolidSet& solids,
                            ReactionAccumulator* reactions, const Float3Array& position,
                            Float3Array& predicted, std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
        const Vec3 before = predicted.get(i);
        std::size_t touched = boundary::kNoSolid;
        const Vec3 after = boundary::resolveSolidCollision(c, solids, position.get(i), before,
                                                           reactions ? &touched : nullptr);
        if (reactions) reactions->add(i, touched, after, after - before);
        predicted.set(i, after);
    }
}

void respondToBoundaries(const SolverConstants& c, const SolidSet* solids, float restitution,
                         float friction, float dt, ReactionAccumulator* reactions,
                         const Float3Array& predicted, Float3Array& velocity, std::size_t begin,
                         std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
        const Vec3 x = predicted.get(i);
        Vec3 v =
            boundary::respondToWalls(c, restitution, friction, x, velocity.get(i));
        if (solids) {
            const Vec3 before = v;
            std::size_t touched = boundary::kNoSolid;
            v = boundary::respondToSolids(*solids, c.particleRadius, restitution, friction, x, v,
                                          reactions ? &touched : nullptr);
            if (reactions) reactions->add(i, touched, x, (v - before) * dt);
        }
        velocity.set(i, v);
    }
}

void commitPositions(const Float3Array& predicted, Float3Array& position, std::size_t begin,
                     std::size_t end) {
    std::copy(predicted.x.begin() + begin, predicted.x.begin() + end, position.x.begin() + begin);
    std::copy(predicted.y.begin() + begin, predicted.y.begin() + end, position.y.begin() + begin);
    std::copy(predicted.z.begin() + begin, predicted.z.begin() + end, position.z.begin() + begin);
}

}  // namespace pbf::stages
