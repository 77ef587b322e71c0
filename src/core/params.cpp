#include "pbf/params.hpp"

#include <cmath>
#include <sstream>

#include "backend/cpu/neighbor_search.hpp"

namespace pbf {
namespace {

bool finite(const Vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// Builds "field: must be in [lo, hi], got value".
template <class T>
std::string outOfRange(const char* field, T value, T lo, T hi) {
    std::ostringstream s;
    s << field << ": must be in [" << lo << ", " << hi << "], got " << value;
    return s.str();
}

template <class T>
bool inRange(T value, T lo, T hi) {
    return value >= lo && value <= hi;  // false for NaN
}

}  // namespace

std::string validate(const SimulationParams& p) {
    if (!finite(p.domain.min) || !finite(p.domain.max)) return "domain: coordinates must be finite";
    const Vec3 e = p.domain.extent();
    if (!(e.x > 0 && e.y > 0 && e.z > 0))
        return "domain: max must be greater than min on every axis";
    if (!finite(p.gravity) || length(p.gravity) > 1000.0f)
        return "gravity: must be finite with magnitude <= 1000 m/s^2";
    if (!inRange(p.particleRadius, 1e-5f, 1.0f))
        return outOfRange("particle_radius", p.particleRadius, 1e-5f, 1.0f);
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

    const FluidParams& f = p.fluid;
    if (!(f.restDensity > 0.0f && f.restDensity <= 1e5f))
        return outOfRange("fluid.rest_density", f.restDensity, 0.0f, 1e5f);
    if (!inRange(f.viscosity, 0.0f, 1.0f))
        return outOfRange("fluid.viscosity", f.viscosity, 0.0f, 1.0f);
    if (!inRange(f.kinematicViscosity, 0.0f, 1.0f))
        return outOfRange("fluid.kinematic_viscosity", f.kinematicViscosity, 0.0f, 1.0f);
    if (!inRange(f.vorticity, 0.0f, 10.0f))
        return outOfRange("fluid.vorticity", f.vorticity, 0.0f, 10.0f);

    const SolverParams& s = p.solver;
    if (!inRange(s.iterations, 1, 100))
        return outOfRange("solver.iterations", s.iterations, 1, 100);
    if (!inRange(s.maxDensityError, 0.0f, 0.1f))
        return outOfRange("solver.max_density_error", s.maxDensityError, 0.0f, 0.1f);
    if (!inRange(s.maxIterations, 1, 1000))
        return outOfRange("solver.max_iterations", s.maxIterations, 1, 1000);
    if (!inRange(s.minIterations, 0, s.maxIterations))
        return outOfRange("solver.min_iterations", s.minIterations, 0, s.maxIterations);
    if (!inRange(s.warmStart, 0.0f, 1.0f))
        return outOfRange("solver.warm_start", s.warmStart, 0.0f, 1.0f);
    // kAutomatic (-1) is the default: the solver chooses (params.hpp).
    if (s.overRelaxation != kAutomatic && !inRange(s.overRelaxation, 0.5f, 1.5f))
        return outOfRange("solver.over_relaxation", s.overRelaxation, 0.5f, 1.5f) +
               " (or -1: automatic)";
    if (!inRange(s.relaxation, 1e-6f, 10.0f))
        return outOfRange("solver.relaxation", s.relaxation, 1e-6f, 10.0f);
    if (!inRange(s.artificialPressure.k, 0.0f, 1.0f))
        return outOfRange("solver.artificial_pressure.k", s.artificialPressure.k, 0.0f, 1.0f);
    if (!inRange(s.artificialPressure.n, 1, 8))
        return outOfRange("solver.artificial_pressure.n", s.artificialPressure.n, 1, 8);
    if (!(s.artificialPressure.dq > 0.0f && s.artificialPressure.dq < 1.0f))
        return outOfRange("solver.artificial_pressure.dq", s.artificialPressure.dq, 0.0f, 1.0f);
    if (!inRange(s.kernelRadiusFactor, 3.0f, 6.0f))
        return outOfRange("solver.kernel_radius_factor", s.kernelRadiusFactor, 3.0f, 6.0f);
    if (!(s.cfl > 0.0f && s.cfl <= 1.0f)) return outOfRange("solver.cfl", s.cfl, 0.0f, 1.0f);
    if (!(s.maxTimeStep > 0.0f && s.maxTimeStep <= 1.0f))
        return outOfRange("solver.max_time_step", s.maxTimeStep, 0.0f, 1.0f);
    if (!inRange(s.maxSubsteps, 1, 10000))
        return outOfRange("solver.max_substeps", s.maxSubsteps, 1, 10000);
    if (!inRange(s.fixedSubsteps, 1, 10000))
        return outOfRange("solver.substeps", s.fixedSubsteps, 1, 10000);
    if (!inRange(s.restitution, 0.0f, 1.0f))
        return outOfRange("solver.restitution", s.restitution, 0.0f, 1.0f);
    if (!inRange(s.friction, 0.0f, 1.0f))
        return outOfRange("solver.friction", s.friction, 0.0f, 1.0f);
    return {};
}

}  // namespace pbf
