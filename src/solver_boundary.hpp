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

// Adds the walls of the domain box within reach of x: their kernel sum and
// the gradient of that sum with respect to x (pointing into the walls).
void addWallContribution(const SolverConstants& c, const Vec3& x, float& kernelSum, Vec3& gradient);

// The nearest solid within reach adds the flat-wall density at its signed
// distance, and its gradient along the surface normal (into the solid).
void addSolidContribution(const SolverConstants& c, const SolidSet* solids, const Vec3& x,
                          float& kernelSum, Vec3& gradient);

}  // namespace pbf::stages
