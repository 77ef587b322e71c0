#include "backend/boundary.hpp"

#include <cmath>

namespace pbf::boundary {
namespace {

// Linear interpolation in the flat-wall table at distance s.
void sampleWallTable(const WallTable& w, float distance, float& kernel, float& gradient) {
    const float t = std::max(distance, 0.0f) * w.inverseStep;
    const int k = std::min(static_cast<int>(t), WallTable::kSamples - 1);
    const float f = t - float(k);
    kernel = w.kernelSum[k] + f * (w.kernelSum[k + 1] - w.kernelSum[k]);
    gradient = w.gradientSum[k] + f * (w.gradientSum[k + 1] - w.gradientSum[k]);
}

// Coulomb friction: the tangential speed drops by mu times the normal speed
// change (1 + e) |v_n|, never below zero. Returns the factor kept.
float frictionKeep(float friction, float restitution, float normalSpeed, float tangentialSpeed) {
    if (!(tangentialSpeed > 0.0f)) return 0.0f;
    return std::max(0.0f, 1.0f - friction * (1.0f + restitution) * normalSpeed / tangentialSpeed);
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

SolidContribution solidContribution(const SolverConstants& c, const SolidSet& solids,
                                    const Vec3& x) {
    SolidContribution s;
    Vec3 normal;
    std::size_t nearest = kNoSolid;
    const float distance = solids.signedDistance(x, c.wall.range, normal, &nearest);
    if (!(distance < c.wall.range)) return s;
    float slope = 0.0f;
    sampleWallTable(c.wall, distance, s.kernelSum, slope);
    s.gradient -= normal * slope;
    s.solid = nearest;
    // A finite body: the flat wall's value scaled to the body's shape
    // (world/boundary_scale.hpp).
    if (solids.hasBoundaryScale(nearest)) {
        const float ratio = solids.boundaryScale(nearest, x);
        s.kernelSum *= ratio;
        s.gradient *= ratio;
    }
    return s;
}

void addNearSolidContribution(const SolverConstants& c, const SolidSet& solids, const Vec3& x,
                              float& kernelSum, Vec3& gradient) {
    const SolidContribution s = solidContribution(c, solids, x);
    if (s.solid == kNoSolid) return;
    kernelSum += s.kernelSum;
    gradient += s.gradient;
}

Vec3 resolveSolidCollision(const SolverConstants& c, const SolidSet& solids, const Vec3& start,
                           Vec3 x, std::size_t* touched) {
    const float radius = c.particleRadius;
    const float reach = c.h;
    const float hitDistance = 0.05f * radius;
    Vec3 normal;
    std::size_t nearest = kNoSolid;
    const Vec3 move = x - start;
    const float moveLength = length(move);
    // Sweep: sphere-trace from the start; the distance field guarantees no
    // surface closer than d, so each step of length d is safe.
    const float startDistance = solids.signedDistance(start, moveLength + reach, normal, &nearest);
    if (startDistance < moveLength && moveLength > 0.0f) {
        const Vec3 direction = move * (1.0f / moveLength);
        float travelled = std::max(startDistance, 0.0f);
        bool hit = startDistance <= hitDistance;
        for (int step = 0; step < 64 && !hit && travelled < moveLength; ++step) {
            const float d = solids.signedDistance(start + direction * travelled, moveLength + reach,
                                                  normal, &nearest);
            if (d <= hitDistance) {
                hit = true;
                break;
            }
            travelled += d;
        }
        if (hit) {
            x = start + direction * std::min(travelled, moveLength);
            if (touched) *touched = nearest;
        }
    }
    // Push out to one radius (twice: a corner between two solids).
    for (int pass = 0; pass < 2; ++pass) {
        const float d = solids.signedDistance(x, reach, normal, &nearest);
        if (!(d < radius)) break;
        x += normal * (radius - d);
        if (touched) *touched = nearest;
    }
    return clampToBox(c.collisionBox, x);
}

Vec3 respondToWalls(const Aabb& box, float restitution, float friction, const Vec3& x, Vec3 v) {
    const float tolerance =
        1e-4f * std::max(1e-6f, box.extent().x + box.extent().y + box.extent().z);
    for (int axis = 0; axis < 3; ++axis) {
        float* vn = axis == 0 ? &v.x : (axis == 1 ? &v.y : &v.z);
        const bool onMin = x[axis] <= box.min[axis] + tolerance && *vn < 0.0f;
        const bool onMax = x[axis] >= box.max[axis] - tolerance && *vn > 0.0f;
        if (!onMin && !onMax) continue;
        const float normalSpeed = std::fabs(*vn);
        *vn = -restitution * *vn;
        float* t1 = axis == 0 ? &v.y : &v.x;
        float* t2 = axis == 2 ? &v.y : &v.z;
        const float keep =
            frictionKeep(friction, restitution, normalSpeed, std::sqrt(*t1 * *t1 + *t2 * *t2));
        *t1 *= keep;
        *t2 *= keep;
    }
    return v;
}

Vec3 respondToSolids(const SolidSet& solids, float radius, float restitution, float friction,
                     const Vec3& x, Vec3 v, std::size_t* touched) {
    const float contact = 1.05f * radius;
    Vec3 normal;
    std::size_t nearest = 0;
    if (!(solids.signedDistance(x, contact, normal, &nearest) < contact)) return v;
    // Relative to the solid's surface: a moving solid carries the water it touches.
    const Vec3 surface =
        solids.anyMoving() ? solids.motion(nearest).velocityAt(x) : Vec3{0.0f, 0.0f, 0.0f};
    const Vec3 relative = v - surface;
    const float vn = dot(relative, normal);
    if (vn >= 0.0f) return v;  // separating
    const Vec3 tangential = relative - normal * vn;
    const float keep = frictionKeep(friction, restitution, -vn, length(tangential));
    if (touched) *touched = nearest;
    return surface + tangential * keep - normal * (restitution * vn);
}

}  // namespace pbf::boundary
