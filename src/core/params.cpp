#include "pbf/core/params.hpp"

#include <cmath>
#include <string>

#include "core/cell_key.hpp"
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
    // Only occupied cells are stored, so the domain's size is limited by the
    // cell key alone: 2^21 cells of the kernel radius a side.
    const double h = p.kernelRadius();
    const double widest = std::fmax(e.x, std::fmax(e.y, e.z));
    cell_key::CellFrame frame;
    if (!cell_key::domainFrame(p.domain, p.kernelRadius(), frame))
        return "particle_radius: the domain is " +
               std::to_string(static_cast<long long>(std::ceil(widest / h))) +
               " kernel radii wide, more than the cell key's " +
               std::to_string(cell_key::kCellsPerAxis) +
               " cells a side; use larger particles or a smaller domain";
    return {};
}

}  // namespace pbf
