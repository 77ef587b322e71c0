// Boundary terms shared by every backend (private header): the projection
// into the domain box, the walls' and solids' contributions to density and
// its gradient, the swept collision with solids and the restitution /
// friction response. Per particle, so that the SIMD passes, the scalar
// reference and a GPU kernel all use the same code.
#pragma once

#include <algorithm>
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

// The nearest solid's share of a particle's density: its kernel sum, the
// gradient of that sum with respect to x (into the solid), and which solid
// it is (kNoSolid and zeros when none is within reach).
struct SolidContribution {
    float kernelSum = 0.0f;
    Vec3 gradient;
    std::size_t solid = kNoSolid;
};
SolidContribution solidContribution(const SolverConstants& c, const SolidSet& solids,
                                    const Vec3& x);

// The out-of-line parts of the two functions below.
void addNearWallContribution(const SolverConstants& c, const Vec3& x, float& kernelSum,
                             Vec3& gradient);
void addNearSolidContribution(const SolverConstants& c, const SolidSet& solids, const Vec3& x,
                              float& kernelSum, Vec3& gradient);

// Adds the walls of the domain box within reach of x: their kernel sum
// (sum of W over the wall's lattice, 1/m^3) and the gradient of that sum
// with respect to x (pointing into the walls). Inline test first: most
// particles are out of every wall's reach.
inline void addWallContribution(const SolverConstants& c, const Vec3& x, float& kernelSum,
                                Vec3& gradient) {
    const float reach = c.wall.range;
    const Aabb& d = c.domain;
    if (x.x - d.min.x >= reach && d.max.x - x.x >= reach && x.y - d.min.y >= reach &&
        d.max.y - x.y >= reach && x.z - d.min.z >= reach && d.max.z - x.z >= reach)
        return;
    addNearWallContribution(c, x, kernelSum, gradient);
}

// The nearest solid within reach adds the flat-wall density at its signed
// distance, and its gradient along the surface normal (into the solid).
inline void addSolidContribution(const SolverConstants& c, const SolidSet* solids, const Vec3& x,
                                 float& kernelSum, Vec3& gradient) {
    if (solids) addNearSolidContribution(c, *solids, x, kernelSum, gradient);
}

// Keeps x at least one particle radius outside every solid. The move from
// `start` (outside, the start of the step) to x is swept by sphere tracing
// the distance field: if it enters a solid, x stops at the surface, so no
// step can carry a particle through a thin wall. Then x is pushed out along
// the surface normal to distance r. Returns the new x, inside the collision box.
// `touched` (may be null) receives the solid that stopped or pushed the
// particle (the last one, at a corner of two), else is left unchanged.
Vec3 resolveSolidCollision(const SolverConstants& c, const SolidSet& solids, const Vec3& start,
                           Vec3 x, std::size_t* touched = nullptr);

// Velocity response of a particle at x touching a wall of the collision box:
// the normal velocity into the wall is reflected with `restitution`; the
// tangential velocity loses Coulomb friction proportional to the normal
// impulse. Returns the new velocity.
Vec3 respondToWalls(const Aabb& box, float restitution, float friction, const Vec3& x, Vec3 v);

// The same against the solids, relative to the velocity of the solid's
// surface at the contact (zero for static solids). `touched` (may be null)
// receives the solid whose contact changed v, else is left unchanged.
Vec3 respondToSolids(const SolidSet& solids, float radius, float restitution, float friction,
                     const Vec3& x, Vec3 v, std::size_t* touched = nullptr);

}  // namespace pbf::boundary
