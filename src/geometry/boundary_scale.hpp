// The boundary density of a finite solid, relative to the flat wall
// (private header).
//
// The boundary term (backend/boundary.hpp) gives a particle at distance s from
// a solid the kernel sum of the rest lattice continued beyond a flat wall at
// that distance. That is exact for the domain walls, but near the edges and
// corners of a small convex body much of that lattice would lie outside the
// body: the term overestimates the solid's density there and pushes water
// away too hard. On a floating 10 cm cube at r = 1 cm (the kernel reaches 4
// cm, so most of each face is "near an edge") the excess push lifted the
// cube by half a particle radius: 0.18 / 0.42 / 0.67 of it submerged at
// densities 250 / 500 / 750 instead of Archimedes' 0.25 / 0.50 / 0.75.
//
// The correction, in the spirit of Koschier & Bender 2017 ("Density maps
// for improved SPH boundary handling"): a grid in the body's own frame
// holds, at each node x, the ratio of the kernel's integral over the body to
// its integral over the half-space beyond the tangent plane at the same
// distance,
//     ratio(x) = int_body W(x - y) dy / int_{half-space at s(x)} W(x - y) dy,
// both by the same quadrature (so its error cancels in the ratio); the
// flat-wall value and its gradient are scaled by the interpolated ratio
// (1 on a flat face far from edges, about 1/2 at an edge, less at a corner).
// The grid is computed once per body shape (rigid: the body frame never
// deforms) and shared by bodies of the same shape.
#pragma once

#include <memory>
#include <vector>

#include "geometry/shape_distance.hpp"
#include "pbf/core/vec3.hpp"
#include "pbf/geometry/solids.hpp"

namespace pbf {

class BoundaryScale {
  public:
    // The ratio grid around `shape` (its own frame) for kernel radius h and
    // flat-wall reach `range` (h - r), nodes `spacing` apart.
    BoundaryScale(const Solid& shape, float h, float range, float spacing);

    // The ratio at `local` (the shape's frame), trilinear; 1 outside the grid.
    float at(const Vec3& local) const { return samples().interpolate(local, 1.0f); }
    // The grid as plain data (for backends that copy it to a device).
    shape::GridSamples samples() const {
        return {box_.min, inverseSpacing_, nx_, ny_, nz_, ratio_.data()};
    }

  private:
    Aabb box_;
    float inverseSpacing_ = 0.0f;
    int nx_ = 0, ny_ = 0, nz_ = 0;
    std::vector<float> ratio_;
};

}  // namespace pbf
