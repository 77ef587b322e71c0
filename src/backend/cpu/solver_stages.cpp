#include "backend/cpu/solver_stages.hpp"

#include <algorithm>
#include <cmath>

#include "backend/boundary.hpp"
#include "backend/reference/equations.hpp"

namespace pbf::stages {
using boundary::clampToBox;

void predictPositions(const SolverStep& s, std::size_t begin, std::size_t end) {
    // By reference, as the stage always read it: a copy lets the compiler
    // hoist dt g out of the loop instead of fusing it into v + dt g, which
    // changes the last bit of v.
    const Vec3& gravity = s.context.params.gravity;
    const float dt = s.dt;
    const Aabb& box = s.context.constants.collisionBox;
    const Float3Array& position = s.particles.position;
    Float3Array& velocity = s.particles.velocity;
    Float3Array& predicted = s.particles.predicted;
    for (std::size_t i = begin; i < end; ++i) {
        const Vec3 v = velocity.get(i) + dt * gravity;
        velocity.set(i, v);
        predicted.set(i, clampToBox(box, position.get(i) + dt * v));
    }
}

void warmStartPredictions(const SolverStep& s, std::size_t begin, std::size_t end) {
    const SolverConstants& c = s.context.constants;
    const float warm = s.context.params.solver.warmStart;
    const float dt = s.dt;
    const Float3Array& solveAcceleration = s.particles.solveAcceleration;
    const float* lastDensity = s.particles.density.data();
    Float3Array& predicted = s.particles.predicted;
    for (std::size_t i = begin; i < end; ++i)
        predicted.set(i,
                      clampToBox(c.collisionBox,
                                 reference::warmStart(c, predicted.get(i), solveAcceleration.get(i),
                                                      lastDensity[i], warm, dt)));
}

void recordSolveAcceleration(const SolverStep& s, std::size_t begin, std::size_t end) {
    const float dt = s.dt;
    const Float3Array& position = s.particles.position;
    const Float3Array& predicted = s.particles.predicted;
    const Float3Array& velocity = s.particles.velocity;
    Float3Array& solveAcceleration = s.particles.solveAcceleration;
    for (std::size_t i = begin; i < end; ++i)
        solveAcceleration.set(i, reference::solveAcceleration(position.get(i), predicted.get(i),
                                                              velocity.get(i), dt));
}

// The neighbour loops below run on full SIMD vectors of neighbours
// (simd.hpp): gather x_j, mask the lanes past the list's end and those
// outside the kernel's support, accumulate per lane, one tree sum at the end.
// Constant factors (the kernels' coefficients) are applied once per particle.

void packPositions(const SolverStep& s, std::size_t begin, std::size_t end) {
    const Float3Array& predicted = s.particles.predicted;
    PackedPoint* packed = s.predicted;
    for (std::size_t i = begin; i < end; ++i)
        packed[i] = {predicted.x[i], predicted.y[i], predicted.z[i], 0.0f};
}

void unpackPositions(const SolverStep& s, std::size_t begin, std::size_t end) {
    const PackedPoint* packed = s.predicted;
    Float3Array& predicted = s.particles.predicted;
    for (std::size_t i = begin; i < end; ++i)
        predicted.set(i, {packed[i].x, packed[i].y, packed[i].z});
}

void packPositionLayers(const SolverStep& s, std::size_t begin, std::size_t end) {
    const PackedPoint* predicted = s.predicted;
    const float* layer = s.surfaceLayer;
    PackedPoint* positionLayer = s.positionLayer;
    for (std::size_t i = begin; i < end; ++i)
        positionLayer[i] = {predicted[i].x, predicted[i].y, predicted[i].z, layer[i]};
}

void updateVelocity(const SolverStep& s, std::size_t begin, std::size_t end) {
    const float inverseDt = 1.0f / s.dt;
    const Float3Array& position = s.particles.position;
    const Float3Array& predicted = s.particles.predicted;
    const float* density = s.particles.density.data();
    Float3Array& velocity = s.particles.velocity;
    PackedPoint* velocityDensity = s.velocityDensity;
    for (std::size_t i = begin; i < end; ++i) {
        const Vec3 v = (predicted.get(i) - position.get(i)) * inverseDt;
        velocity.set(i, v);
        velocityDensity[i] = {v.x, v.y, v.z, density[i]};
    }
}

void applyVorticityConfinement(const SolverStep& s, std::size_t begin, std::size_t end) {
    const SolverConstants& c = s.context.constants;
    const float vorticityEpsilon = s.context.params.fluid.vorticity;
    const float dt = s.dt;
    const NeighborSearch& search = s.search;
    const Float3Array& predicted = s.particles.predicted;
    const Float3Array& vorticity = *s.vorticity;
    const float* density = s.particles.density.data();
    Float3Array& velocity = s.particles.velocity;
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

void applyPhysicalViscosity(const SolverStep& s, std::size_t begin, std::size_t end) {
    const SolverConstants& c = s.context.constants;
    const float nu = s.context.params.fluid.kinematicViscosity;
    const float dt = s.dt;
    const NeighborSearch& search = s.search;
    const PackedPoint* predicted = s.predicted;
    const PackedPoint* velocityDensity = s.velocityDensity;
    Float3Array& velocity = s.particles.velocity;
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

void resolveSolidCollisions(const SolverStep& s, std::size_t begin, std::size_t end) {
    const SolverConstants& c = s.context.constants;
    const SolidSet& solids = *s.solids;
    ReactionAccumulator* reactions = s.reactions;
    const Float3Array& position = s.particles.position;
    Float3Array& predicted = s.particles.predicted;
    for (std::size_t i = begin; i < end; ++i) {
        const Vec3 before = predicted.get(i);
        std::size_t touched = boundary::kNoSolid;
        const Vec3 after = boundary::resolveSolidCollision(c, solids, position.get(i), before,
                                                           reactions ? &touched : nullptr);
        if (reactions) reactions->add(i, touched, after, after - before);
        predicted.set(i, after);
    }
}

void respondToBoundaries(const SolverStep& s, std::size_t begin, std::size_t end) {
    const SolverConstants& c = s.context.constants;
    const SolidSet* solids = s.solids;
    const float restitution = s.context.params.solver.restitution;
    const float friction = s.context.params.solver.friction;
    const float dt = s.dt;
    ReactionAccumulator* reactions = s.reactions;
    const Float3Array& predicted = s.particles.predicted;
    Float3Array& velocity = s.particles.velocity;
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

void commitPositions(const SolverStep& s, std::size_t begin, std::size_t end) {
    const Float3Array& predicted = s.particles.predicted;
    Float3Array& position = s.particles.position;
    std::copy(predicted.x.begin() + begin, predicted.x.begin() + end, position.x.begin() + begin);
    std::copy(predicted.y.begin() + begin, predicted.y.begin() + end, position.y.begin() + begin);
    std::copy(predicted.z.begin() + begin, predicted.z.begin() + end, position.z.begin() + begin);
}

}  // namespace pbf::stages
