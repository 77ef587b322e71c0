// A containment check that can fail. Positions are clamped into the
// collision box, so "no particle outside the domain" holds by construction
// and catches nothing. A solver that pushes particles into a wall (a wrong
// sign in the wall's density gradient, a missing boundary term) shows up
// instead as particles piled onto the clamp plane: more of them within a
// quarter radius of a wall than one layer of the rest lattice holds, packed
// closer than any fluid does.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

#include "pbf/core/params.hpp"
#include "pbf/core/particles.hpp"

namespace pbf::test {

struct WallLayers {
    double worstFill = 0.0;     // particles on a wall / what one rest layer holds, worst wall
    std::string worstWall;      // "x min", ...
    double closestPair = 1e30;  // smallest distance between two particles on a wall, m
};

inline WallLayers wallLayers(const ParticleStore& p, const SimulationParams& params) {
    const float r = params.particleRadius;
    const float spacing = params.particleSpacing();
    const Aabb box{params.domain.min + Vec3{r, r, r}, params.domain.max - Vec3{r, r, r}};
    const Vec3 extent = params.domain.extent();
    WallLayers result;
    const char* names[3] = {"x", "y", "z"};
    for (int axis = 0; axis < 3; ++axis) {
        for (int side = 0; side < 2; ++side) {
            const float plane = side == 0 ? box.min[axis] : box.max[axis];
            std::vector<Vec3> layer;
            for (std::size_t i = 0; i < p.size(); ++i) {
                const Vec3 x = p.position.get(i);
                if (std::fabs(x[axis] - plane) < 0.25f * r) layer.push_back(x);
            }
            const double area = double(extent[(axis + 1) % 3]) * extent[(axis + 2) % 3];
            const double fill = double(layer.size()) / (area / (double(spacing) * spacing));
            if (fill > result.worstFill) {
                result.worstFill = fill;
                result.worstWall = std::string(names[axis]) + (side == 0 ? " min" : " max");
            }
            for (std::size_t a = 0; a < layer.size(); ++a)
                for (std::size_t b = a + 1; b < layer.size(); ++b)
                    result.closestPair =
                        std::min(result.closestPair, double(length(layer[a] - layer[b])));
        }
    }
    return result;
}

}  // namespace pbf::test
