#include "backend/cpu/solver_stages.hpp"

#include <algorithm>
#include <cmath>

#include "backend/cpu/solver_boundary.hpp"

namespace pbf::stages {
namespace {

// Linear interpolation in the flat-wall table at distance s.
void sampleWallTable(const WallTable& w, float distance, float& kernel, float& gradient) {
    const float t = std::max(distance, 0.0f) * w.inverseStep;
    const int k = std::min(static_cast<int>(t), WallTable::kSamples - 1);
    const float f = t - float(k);
    kernel = w.kernelSum[k] + f * (w.kernelSum[k + 1] - w.kernelSum[k]);
    gradient = w.gradientSum[k] + f * (w.gradientSum[k + 1] - w.gradientSum[k]);
}

}  // namespace

void addNearWallContribution(const SolverConstants& c, const Vec3& x, float& kernelSum,
                             Vec3& gradient) {
    const WallTable& w = c.wall;
    auto add = [&](float distance, float Vec3::*axis, float outward) {
        if (!(distance < w.range)) return;
        float kernel = 0.0f, slope = 0.0f;
        sampleWallTable(w, distance, kernel, slope);
        kernelSum += kernel;
        gradient.*axis += outward * slope;
    };
    add(x.x - c.domain.min.x, &Vec3::x, -1.0f);
    add(c.domain.max.x - x.x, &Vec3::x, 1.0f);
    add(x.y - c.domain.min.y, &Vec3::y, -1.0f);
    add(c.domain.max.y - x.y, &Vec3::y, 1.0f);
    add(x.z - c.domain.min.z, &Vec3::z, -1.0f);
    add(c.domain.max.z - x.z, &Vec3::z, 1.0f);
}

void addNearSolidContribution(const SolverConstants& c, const SolidSet& solids, const Vec3& x,
                              float& kernelSum, Vec3& gradient) {
    Vec3 normal;
    const float distance = solids.signedDistance(x, c.wall.range, normal);
    if (!(distance < c.wall.range)) return;
    float kernel = 0.0f, slope = 0.0f;
    sampleWallTable(c.wall, distance, kernel, slope);
    kernelSum += kernel;
    gradient -= normal * slope;
}

void predictPositions(const Vec3& gravity, float dt, const Aabb& box, const Float3Array& position,
                      Float3Array& velocity, Float3Array& predicted, std::size_t begin,
                      std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
        const Vec3 v = velocity.get(i) + dt * gravity;
        velocity.set(i, v);
        predicted.set(i, clampToBox(box, position.get(i) + dt * v));
    }
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

void respondToWalls(const Aabb& box, float restitution, float friction,
                    const Float3Array& predicted, Float3Array& velocity, std::size_t begin,
                    std::size_t end) {
    const float tolerance =
        1e-4f * std::max(1e-6f, box.extent().x + box.extent().y + box.extent().z);
    for (std::size_t i = begin; i < end; ++i) {
        const Vec3 x = predicted.get(i);
        Vec3 v = velocity.get(i);
        for (int axis = 0; axis < 3; ++axis) {
            float* vn = axis == 0 ? &v.x : (axis == 1 ? &v.y : &v.z);
            const bool onMin = x[axis] <= box.min[axis] + tolerance && *vn < 0.0f;
            const bool onMax = x[axis] >= box.max[axis] - tolerance && *vn > 0.0f;
            if (!onMin && !onMax) continue;
            const float normalSpeed = std::fabs(*vn);
            *vn = -restitution * *vn;
            // Coulomb friction: the tangential speed drops by mu times the
            // normal speed change, never below zero.
            float* t1 = axis == 0 ? &v.y : &v.x;
            float* t2 = axis == 2 ? &v.y : &v.z;
            const float tangential = std::sqrt(*t1 * *t1 + *t2 * *t2);
            if (tangential > 0.0f) {
                const float keep = std::max(
                    0.0f, 1.0f - friction * (1.0f + restitution) * normalSpeed / tangential);
                *t1 *= keep;
                *t2 *= keep;
            }
        }
        velocity.set(i, v);
    }
}

Vec3 resolveSolidCollision(const SolverConstants& c, const SolidSet& solids, float radius,
                           const Vec3& start, Vec3 x) {
    const float reach = c.h;
    const float hitDistance = 0.05f * radius;
    Vec3 normal;
    const Vec3 move = x - start;
    const float moveLength = length(move);
    // Sweep: sphere-trace from the start; the distance field guarantees no
    // surface closer than d, so each step of length d is safe.
    const float startDistance = solids.signedDistance(start, moveLength + reach, normal);
    if (startDistance < moveLength && moveLength > 0.0f) {
        const Vec3 direction = move * (1.0f / moveLength);
        float travelled = std::max(startDistance, 0.0f);
        bool hit = startDistance <= hitDistance;
        for (int step = 0; step < 64 && !hit && travelled < moveLength; ++step) {
            const float d =
                solids.signedDistance(start + direction * travelled, moveLength + reach, normal);
            if (d <= hitDistance) {
                hit = true;
                break;
            }
            travelled += d;
        }
        if (hit) x = start + direction * std::min(travelled, moveLength);
    }
    // Push out to one radius (twice: a corner between two solids).
    for (int pass = 0; pass < 2; ++pass) {
        const float d = solids.signedDistance(x, reach, normal);
        if (!(d < radius)) break;
        x += normal * (radius - d);
    }
    return clampToBox(c.collisionBox, x);
}

void resolveSolidCollisions(const SolverConstants& c, const SolidSet& solids, float radius,
                            const Float3Array& position, Float3Array& predicted, std::size_t begin,
                            std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
        predicted.set(i,
                      resolveSolidCollision(c, solids, radius, position.get(i), predicted.get(i)));
}

void respondToSolids(const SolidSet& solids, float radius, float restitution, float friction,
                     const Float3Array& predicted, Float3Array& velocity, std::size_t begin,
                     std::size_t end) {
    const float contact = 1.05f * radius;
    for (std::size_t i = begin; i < end; ++i) {
        Vec3 normal;
        if (!(solids.signedDistance(predicted.get(i), contact, normal) < contact)) continue;
        Vec3 v = velocity.get(i);
        const float vn = dot(v, normal);
        if (vn >= 0.0f) continue;  // separating
        const Vec3 tangential = v - normal * vn;
        const float tangentialSpeed = length(tangential);
        const float keep =
            tangentialSpeed > 0.0f
                ? std::max(0.0f, 1.0f - friction * (1.0f + restitution) * -vn / tangentialSpeed)
                : 0.0f;
        v = tangential * keep - normal * (restitution * vn);
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
