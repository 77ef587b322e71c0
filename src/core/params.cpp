#include "pbf/core/params.hpp"

#include <cmath>
#include <string>

#include "core/grid_limits.hpp"
#include "pbf/core/param_table.hpp"

namespace pbf {

std::string validate(const SimulationParams& p) {
    // Each parameter's own range (the table's rows, in their order).
    for (const ParamInfo& param : paramTable())
        if (std::string problem = param.check(p); !problem.empty()) return problem;

    // What depends on several: the grid of kernel-radius cells the domain holds.
    const Vec3 e = p.domain.extent();
    const float minExtent = std::fmin(e.x, std::fmin(e.y, e.z));
    if (2.0f * p.kernelRadius() > minExtent)
        return "particle_radius: the domain must be at least two kernel radii (" +
               std::to_string(p.solver.kernelRadiusFactor) + " r each) wide on every axis";
    const double h = p.kernelRadius();
    const double cells = std::ceil(e.x / h) * std::ceil(e.y / h) * std::ceil(e.z / h);
    if (cells > double(kMaxGridCells))
        return "particle_radius: the domain holds " +
               std::to_string(static_cast<long long>(cells)) +
               " grid cells of the kernel radius, more than the limit of " +
               std::to_string(kMaxGridCells) + "; use larger particles or a smaller domain";
    return {};
}

}  // namespace pbf
