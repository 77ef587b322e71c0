// Boundary terms shared by the solver's stages and its SIMD neighbour passes
// (neighbor_passes.cpp): the box projection, the walls' and solids'
// contributions to density and its gradient. Private header.
#pragma once

#include <algorithm>

#include "pbf/solids.hpp"
#include "pbf/solver.hpp"
#include "pbf/vec3.hpp"

namespace pbf::stages {

inline Vec3 clampToBox(const Aabb& box, const Vec3& p) {
    return {std::clamp(p.x, box.min.x, box.max.x), std::clamp(p.y, box.min.y, box.max.y),
            std::clamp(p.z, box.min.z, box.max.z)};
}

// The out-of-line parts of the two functions below.
void addNearWallContribution(const SolverConstants& c, const Vec3& x, float& kernelSum,
                             Vec3& gradient);
void addNearSolidContribution(const SolverConstants& c, const SolidSet& solids, const Vec3& x,
                              float& kernelSum, Vec3& gradient);

// Adds the walls of the domain box within reach of x: their kernel sum and
// the gradient of that sum with respect to x (pointing into the walls).
// Inline test first: most particles are out of every wall's reach.
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

}  // namespace pbf::stages
