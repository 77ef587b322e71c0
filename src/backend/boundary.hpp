// Boundary terms shared by every backend (private header): the projection
// into the domain box, the walls' and solids' contributions to density and
// its gradient, the swept collision with solids and the restitution /
// friction response. Per particle and PBF_HD, so that the SIMD passes, the
// scalar reference and the GPU backend's kernels all run this code.
//
// The solid functions are templates over the solids' type: the host's
// SolidSet (include/pbf/geometry/solids.hpp) or the GPU backend's device view of the
// same solids (backend/gpu/device_solids.hpp). Both answer
//   signedDistance(p, reach, normal, &nearest)  the nearest solid within reach
//   hasBoundaryScale(k), boundaryScale(k, p)    a finite body's density ratio
//   anyMoving(), motion(k).velocityAt(p)        the surface's velocity
// with the same semantics.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

#include "pbf/core/config.hpp"
#include "pbf/core/solver_constants.hpp"
#include "pbf/core/vec3.hpp"
#include "pbf/geometry/solids.hpp"

namespace pbf::boundary {

PBF_HD inline Vec3 clampToBox(const Aabb& box, const Vec3& p) {
    return {std::clamp(p.x, box.min.x, box.max.x), std::clamp(p.y, box.min.y, box.max.y),
            std::clamp(p.z, box.min.z, box.max.z)};
}

// "No solid" for the functions below that name the solid a particle touched.
inline constexpr std::size_t kNoSolid = std::numeric_limits<std::size_t>::max();

// Linear interpolation in a column of the flat-wall table at distance s.
PBF_HD inline float sampleWall(const float (&column)[WallTable::kSamples + 1], const WallTable& w,
                               float distance) {
    const float t = std::max(distance, 0.0f) * w.inverseStep;
    const int k = std::min(static_cast<int>(t), WallTable::kSamples - 1);
    const float f = t - float(k);
    return column[k] + f * (column[k + 1] - column[k]);
}

PBF_HD inline void sampleWallTable(const WallTable& w, float distance, float& kernel,
                                   float& gradient) {
    kernel = sampleWall(w.kernelSum, w, distance);
    gradient = sampleWall(w.gradientSum, w, distance);
}

// Coulomb friction: the tangential speed drops by mu times the normal speed
// change (1 + e) |v_n|, never below zero. Returns the factor kept.
PBF_HD inline float frictionKeep(float friction, float restitution, float normalSpeed,
                                 float tangentialSpeed) {
    if (!(tangentialSpeed > 0.0f)) return 0.0f;
    return std::max(0.0f, 1.0f - friction * (1.0f + restitution) * normalSpeed / tangentialSpeed);
}

// The walls of the domain box within reach of x: their kernel sum (sum of
// W over the wall's lattice, 1/m^3) and the gradient of that sum with
// respect to x (pointing into the walls).
PBF_HD inline void addNearWallContribution(const SolverConstants& c, const Vec3& x,
                                           float& kernelSum, Vec3& gradient) {
    const WallTable& w = c.wall;
    float* g[3] = {&gradient.x, &gradient.y, &gradient.z};
    const auto add = [&](float distance, int axis, float outward) {
        if (!(distance < w.range)) return;
        float kernel = 0.0f, slope = 0.0f;
        sampleWallTable(w, distance, kernel, slope);
        kernelSum += kernel;
        *g[axis] += outward * slope;
    };
    add(x.x - c.domain.min.x, 0, -1.0f);
    add(c.domain.max.x - x.x, 0, 1.0f);
    add(x.y - c.domain.min.y, 1, -1.0f);
    add(c.domain.max.y - x.y, 1, 1.0f);
    add(x.z - c.domain.min.z, 2, -1.0f);
    add(c.domain.max.z - x.z, 2, 1.0f);
}

// Adds the walls within reach of x (addNearWallContribution). Inline test
// first: most particles are out of every wall's reach.
PBF_HD inline void addWallContribution(const SolverConstants& c, const Vec3& x, float& kernelSum,
                                       Vec3& gradient) {
    const float reach = c.wall.range;
    const Aabb& d = c.domain;
    if (x.x - d.min.x >= reach && d.max.x - x.x >= reach && x.y - d.min.y >= reach &&
        d.max.y - x.y >= reach && x.z - d.min.z >= reach && d.max.z - x.z >= reach)
        return;
    addNearWallContribution(c, x, kernelSum, gradient);
}

// The nearest solid's share of a particle's density: its kernel sum, the
// gradient of that sum with respect to x (into the solid), and which solid
// it is (kNoSolid and zeros when none is within reach). The solid adds the
// flat-wall density at its signed distance, along its surface normal.
struct SolidContribution {
    float kernelSum = 0.0f;
    Vec3 gradient;
    std::size_t solid = kNoSolid;
};

template <class Solids>
PBF_HD SolidContribution solidContribution(const SolverConstants& c, const Solids& solids,
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
    // (geometry/boundary_scale.hpp).
    if (solids.hasBoundaryScale(nearest)) {
        const float ratio = solids.boundaryScale(nearest, x);
        s.kernelSum *= ratio;
        s.gradient *= ratio;
    }
    return s;
}

// Adds the nearest solid's contribution (solidContribution); `solids` may be null.
template <class Solids>
PBF_HD void addSolidContribution(const SolverConstants& c, const Solids* solids, const Vec3& x,
                                 float& kernelSum, Vec3& gradient) {
    if (!solids) return;
    const SolidContribution s = solidContribution(c, *solids, x);
    if (s.solid == kNoSolid) return;
    kernelSum += s.kernelSum;
    gradient += s.gradient;
}

// Adhesion (surface tension on; Akinci et al. 2013 eq. 6 with the
// distance-field boundary): the walls and the nearest solid pull a particle
// as the rest lattice continued beyond their surface would (WallTable::
// cohesionSum), times their adhesion (the work of adhesion in units of the
// water's 2 sigma). `walls` is the domain walls' share, `solid` the nearest
// solid's (index `solidIndex`, kNoSolid when none pulls): weighted table
// values (m^5; times SolverConstants::cohesionScale an acceleration),
// pointing into the boundary. Zero where every adhesion within reach is zero.
struct AdhesionPull {
    Vec3 walls;
    Vec3 solid;
    std::size_t solidIndex = kNoSolid;
};
template <class Solids>
PBF_HD AdhesionPull adhesionPull(const SolverConstants& c, float wallAdhesion, const Solids* solids,
                                 const Vec3& x) {
    AdhesionPull pull;
    const WallTable& w = c.wall;
    if (wallAdhesion > 0.0f) {
        // `into`: the direction from x into the wall along the axis.
        float* p[3] = {&pull.walls.x, &pull.walls.y, &pull.walls.z};
        const auto add = [&](float distance, int axis, float into) {
            if (distance < w.range)
                *p[axis] += into * wallAdhesion * sampleWall(w.cohesionSum, w, distance);
        };
        const Aabb& d = c.domain;
        add(x.x - d.min.x, 0, -1.0f);
        add(d.max.x - x.x, 0, 1.0f);
        add(x.y - d.min.y, 1, -1.0f);
        add(d.max.y - x.y, 1, 1.0f);
        add(x.z - d.min.z, 2, -1.0f);
        add(d.max.z - x.z, 2, 1.0f);
    }
    if (!solids) return pull;
    Vec3 normal;
    std::size_t nearest = kNoSolid;
    const float distance = solids->signedDistance(x, w.range, normal, &nearest);
    if (!(distance < w.range) || !(solids->adhesion(nearest) > 0.0f)) return pull;
    float strength = solids->adhesion(nearest) * sampleWall(w.cohesionSum, w, distance);
    // A finite body: scaled like its density share (the poly6 kernel's ratio
    // of the body to the half-space, geometry/boundary_scale.hpp; for the
    // pull, a gradient sum, an approximation that keeps corners from pulling
    // as hard as flat walls).
    if (solids->hasBoundaryScale(nearest)) strength *= solids->boundaryScale(nearest, x);
    pull.solid = normal * -strength;
    pull.solidIndex = nearest;
    return pull;
}

// Keeps x at least one particle radius outside every solid. The move from
// `start` (outside, the start of the step) to x is swept by sphere tracing
// the distance field: if it enters a solid, x stops at the surface, so no
// step can carry a particle through a thin wall. Then x is pushed out along
// the surface normal to distance r. Returns the new x, inside the collision box.
// `touched` (may be null) receives the solid that stopped or pushed the
// particle (the last one, at a corner of two), else is left unchanged.
template <class Solids>
PBF_HD Vec3 resolveSolidCollision(const SolverConstants& c, const Solids& solids, const Vec3& start,
                                  Vec3 x, std::size_t* touched = nullptr) {
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

// Velocity response of a particle at x touching a wall of the collision box:
// the normal velocity into the wall is reflected with `restitution`; the
// tangential velocity loses Coulomb friction proportional to the normal
// impulse. Returns the new velocity. A particle within 1 % of its radius of
// a wall touches it (collisions clamp x onto the walls exactly; the margin
// takes the particles the density correction left just off them), plus a
// few float roundings of the wall's coordinate: the particles' scale, not
// the domain's (a share of the domain made every particle within 12 mm of a
// 60 m basin's floor a contact).
PBF_HD inline Vec3 respondToWalls(const SolverConstants& c, float restitution, float friction,
                                  const Vec3& x, Vec3 v) {
    const Aabb& box = c.collisionBox;
    for (int axis = 0; axis < 3; ++axis) {
        const float lo = std::fabs(box.min[axis]), hi = std::fabs(box.max[axis]);
        const float magnitude = lo > hi ? lo : hi;
        const float tolerance = 0.01f * c.particleRadius +
                                8.0f * std::numeric_limits<float>::epsilon() *
                                    (magnitude > 1e-3f ? magnitude : 1e-3f);
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

// The same against the solids, relative to the velocity of the solid's
// surface at the contact (zero for static solids). `touched` (may be null)
// receives the solid whose contact changed v, else is left unchanged.
template <class Solids>
PBF_HD Vec3 respondToSolids(const Solids& solids, float radius, float restitution, float friction,
                            const Vec3& x, Vec3 v, std::size_t* touched = nullptr) {
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
