#include "pbf/core/param_table.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace pbf {
namespace {

template <class Group>
constexpr ParamGroup groupOf();
template <>
constexpr ParamGroup groupOf<SimulationParams>() {
    return ParamGroup::Simulation;
}
template <>
constexpr ParamGroup groupOf<FluidParams>() {
    return ParamGroup::Fluid;
}
template <>
constexpr ParamGroup groupOf<SolverParams>() {
    return ParamGroup::Solver;
}
template <>
constexpr ParamGroup groupOf<ArtificialPressureParams>() {
    return ParamGroup::ArtificialPressure;
}

template <class T>
constexpr ParamType typeOf();
template <>
constexpr ParamType typeOf<float>() {
    return ParamType::Float;
}
template <>
constexpr ParamType typeOf<int>() {
    return ParamType::Int;
}
template <>
constexpr ParamType typeOf<Vec3>() {
    return ParamType::Vec3;
}
template <>
constexpr ParamType typeOf<Aabb>() {
    return ParamType::Box;
}
template <>
constexpr ParamType typeOf<TimeStepMode>() {
    return ParamType::Choice;
}

// Type-checked accessors of one member: the value's alternative is the
// member's type.
template <class Group, class T, T Group::*Member>
ParamValue getMember(const void* group) {
    return static_cast<const Group*>(group)->*Member;
}
template <class Group, class T, T Group::*Member>
void setMember(void* group, const ParamValue& value) {
    static_cast<Group*>(group)->*Member = std::get<T>(value);
}

struct Row {
    std::string_view path, attribute, unit;
    ParamRange range;
    bool live;
    std::string_view description;
    std::string_view rangeText = {};
    std::string_view defaultText = {};
    bool required = false;
};

template <class Group, class T, T Group::*Member>
ParamInfo param(const Row& row) {
    return ParamInfo{row.path,
                     row.attribute,
                     groupOf<Group>(),
                     typeOf<T>(),
                     row.unit,
                     row.range,
                     row.live,
                     row.required,
                     row.description,
                     row.rangeText,
                     row.defaultText,
                     &getMember<Group, T, Member>,
                     &setMember<Group, T, Member>};
}

#define PBF_PARAM(Group, member, ...) \
    param<Group, decltype(Group::member), &Group::member>(Row{__VA_ARGS__})

constexpr bool kLive = true;
constexpr bool kFixed = false;

// Ranges: closed [lo, hi] unless an end is marked open.
constexpr ParamRange closed(double lo, double hi) {
    return {lo, hi, false, false};
}
constexpr ParamRange openClosed(double lo, double hi) {
    return {lo, hi, true, false};
}
constexpr ParamRange open(double lo, double hi) {
    return {lo, hi, true, true};
}

// clang-format off
const ParamInfo kTable[] = {
    PBF_PARAM(SimulationParams, domain, "domain", "domain", "m", {}, kFixed,
              "{\"min\": [x, y, z], \"max\": [x, y, z]}: the box that holds the water; particles "
              "never leave it (its six walls are solid). It may lie anywhere: far from the origin "
              "the solver measures positions from the domain's centre, so the water is as "
              "accurate at 10 km as at 0 m (the numbers in the file are floats: 0.5 mm apart at "
              "10 km)",
              "`max > min` on every axis, finite", "required", true),
    PBF_PARAM(SimulationParams, gravity, "gravity", "gravity", "m/s²", {0.0, 1000.0}, kLive,
              "gravitational acceleration", "finite, magnitude ≤ 1000"),
    PBF_PARAM(SimulationParams, particleRadius, "particle_radius", "particle_radius", "m",
              closed(1e-5, 1.0), kFixed,
              "particles start on a cubic lattice of spacing 2 r; each carries the mass of one "
              "lattice cell of water",
              "[1e-5, 1]; the domain must be ≥ 2 kernel radii wide and ≤ 2^21 kernel radii on "
              "its longest side",
              "required", true),
    PBF_PARAM(FluidParams, restDensity, "fluid.rest_density", "rest_density", "kg/m³",
              openClosed(0.0, 1e5), kLive, "ρ0"),
    PBF_PARAM(FluidParams, viscosity, "fluid.viscosity", "viscosity", "1", closed(0.0, 1.0), kLive,
              "XSPH viscosity c (Macklin & Müller eq. 17, Schechter & Bridson 2012): a smoothing of "
              "the velocities by a share c per substep, not a viscosity in m²/s (its effect depends "
              "on dt and r; for one use `kinematic_viscosity`)"),
    PBF_PARAM(FluidParams, kinematicViscosity, "fluid.kinematic_viscosity", "kinematic_viscosity",
              "m²/s", closed(0.0, 1.0), kLive,
              "kinematic viscosity ν: the SPH Laplacian of the velocity (Monaghan 2005), a "
              "material viscosity whose Taylor–Green decay matches ν within 10 % "
              "([validation](validation.md#taylor_green)); 0: none (water is 1e-6, below PBF's "
              "own dissipation). Explicit: the adaptive substep keeps ν dt ≤ 0.05 (2 r)²"),
    PBF_PARAM(FluidParams, vorticity, "fluid.vorticity", "vorticity", "1", closed(0.0, 10.0), kLive,
              "vorticity confinement ε (eq. 16): acceleration ε h \\|ω\\| (N × ω)"),
    PBF_PARAM(FluidParams, surfaceTension, "fluid.surface_tension", "surface_tension", "N/m",
              closed(0.0, 10.0), kLive,
              "surface tension σ (water at 20 °C: 0.0728); 0: off. Drops round up, streams "
              "pinch off, water wets or beads on solids ([surface tension](surface_tension.md)); "
              "with it on the substep is also limited by the capillary time step and "
              "`solver.artificial_pressure` is off"),
    PBF_PARAM(SolverParams, iterations, "solver.iterations", "iterations", "", closed(1, 100),
              kLive, "Jacobi density iterations per substep"),
    PBF_PARAM(SolverParams, maxDensityError, "solver.max_density_error", "max_density_error", "1",
              closed(0.0, 0.1), kLive,
              "iterate each substep until the average compression mean(max(ρ/ρ0 − 1, 0)) is at "
              "most this (e.g. 0.0002 = 0.02 %; SPlisHSPlasH's `maxError`); 0: fixed `iterations` "
              "([accuracy per cost](performance.md#accuracy-per-cost-iterating-to-a-tolerance)). With a tolerance "
              "the over-relaxed iteration is the default (`over_relaxation` 1.2); set "
              "`over_relaxation` 1 for plain Jacobi"),
    PBF_PARAM(SolverParams, minIterations, "solver.min_iterations", "min_iterations", "",
              (ParamRange{0, 0, false, false, "solver.max_iterations"}), kLive,
              "with `max_density_error`: corrections run at least", "[0, `max_iterations`]"),
    PBF_PARAM(SolverParams, maxIterations, "solver.max_iterations", "max_iterations", "",
              closed(1, 1000), kLive, "with `max_density_error`: corrections run at most"),
    PBF_PARAM(SolverParams, overRelaxation, "solver.over_relaxation", "over_relaxation", "1",
              (ParamRange{0.5, 1.5, false, false, {}, kAutomatic}), kLive,
              "ω of the Jacobi correction x* += ω Δp (Macklin et al. 2014, sec. 4.2); 1: the "
              "paper's PBF. Automatic (-1, the default): 1.2 with `max_density_error` > 0, else 1",
              "[0.5, 1.5] or -1", "automatic"),
    PBF_PARAM(SolverParams, warmStart, "solver.warm_start", "warm_start", "1", closed(0.0, 1.0),
              kLive,
              "start each substep's iterations from the prediction plus this fraction of the "
              "particle's last solve acceleration × dt², for particles that ended the last "
              "substep compressed; 0: off. 0.8 with `over_relaxation` 1.2 and at least 4 "
              "iterations was the best on the dam break ([accuracy per "
              "cost](performance.md#accuracy-per-cost-iterating-to-a-tolerance)), but it makes water at rest boil "
              "(0.3 m/s in a resting tank): not for scenes that come to rest"),
    PBF_PARAM(SolverParams, relaxation, "solver.relaxation", "relaxation", "1",
              closed(1e-6, 10.0), kLive,
              "constraint-force-mixing ε of eq. 11, relative to the rest lattice's Σ\\|∇C\\|²"),
    PBF_PARAM(SolverParams, consistentCorrection, "solver.consistent_correction",
              "consistent_correction", "1", closed(0.0, 1.0), kLive,
              "β: eq. 14's weight λ_i + λ_j becomes (1 − 2β) λ_i + λ_j. The paper's form (0) "
              "conserves momentum but holds compressed water stiff against shear in proportion "
              "to its pressure: waves run fast and are damped ([standing "
              "wave](validation.md#standing-wave-frequency-and-decay)). 0.45 gives the standing "
              "wave's frequency within 2 % and a third less damping, and a shaken tank's "
              "resonance; but water at rest is noisier (above about 0.35), momentum is conserved "
              "only where the λ are uniform, and floating bodies are wrong: for wave tanks "
              "without bodies"),
    PBF_PARAM(ArtificialPressureParams, k, "solver.artificial_pressure.k", "scorr_k", "1",
              closed(0.0, 1.0), kLive,
              "s_corr strength (eq. 13), in units of the constraint (see below)"),
    PBF_PARAM(ArtificialPressureParams, n, "solver.artificial_pressure.n", "scorr_n", "",
              closed(1, 8), kLive, "s_corr exponent"),
    PBF_PARAM(ArtificialPressureParams, dq, "solver.artificial_pressure.dq", "scorr_dq", "1",
              open(0.0, 1.0), kLive, "s_corr reference distance as a fraction of h"),
    PBF_PARAM(SolverParams, kernelRadiusFactor, "solver.kernel_radius_factor",
              "kernel_radius_factor", "1", closed(3.0, 6.0), kFixed,
              "kernel support h in particle radii (h = 4 r gives ~30 neighbours)"),
    PBF_PARAM(SolverParams, timeStepMode, "solver.time_step", "time_step", "", {}, kLive,
              "how substeps are chosen: CFL-limited, or `substeps` per frame",
              "`\"adaptive\"` or `\"fixed\"`"),
    PBF_PARAM(SolverParams, cfl, "solver.cfl", "cfl", "1", openClosed(0.0, 1.0), kLive,
              "adaptive: substep = cfl × spacing / (max speed + g × max_time_step)"),
    PBF_PARAM(SolverParams, maxTimeStep, "solver.max_time_step", "max_time_step", "s",
              openClosed(0.0, 1.0), kLive, "adaptive: upper bound of a substep", "", "1/240"),
    PBF_PARAM(SolverParams, maxSubsteps, "solver.max_substeps", "max_substeps", "",
              closed(1, 10000), kLive, "adaptive: at most this many substeps per frame (surface tension's capillary time step, a limit of stability, overrides it)"),
    PBF_PARAM(SolverParams, depthLimit, "solver.depth_limit", "depth_limit", "1", closed(0.0, 1.0),
              kLive,
              "adaptive, fixed iterations: substep ≤ spacing × √(depth_limit × iterations / (g × "
              "depth)), the depth the fluid blocks start with; deeper water at a longer step "
              "erupts as it starts ([deep water](scenes.md#deep-water-how-long-a-substep-may-be)); 0: off"),
    PBF_PARAM(SolverParams, fixedSubsteps, "solver.substeps", "substeps", "", closed(1, 10000),
              kLive, "fixed: substeps per frame"),
    PBF_PARAM(SolverParams, restitution, "solver.restitution", "restitution", "1",
              closed(0.0, 1.0), kLive, "walls: share of the normal velocity reflected"),
    PBF_PARAM(SolverParams, friction, "solver.friction", "friction", "1", closed(0.0, 1.0), kLive,
              "walls: Coulomb friction coefficient (tangential speed lost per normal speed "
              "stopped)"),
    PBF_PARAM(SolverParams, wallAdhesion, "solver.wall_adhesion", "wall_adhesion", "1",
              closed(0.0, 1.0), kLive,
              "with surface tension: how strongly water wets the domain walls, the work of "
              "adhesion in units of 2σ; Young–Dupré contact angle acos(2a − 1): 0 beads (180°), "
              "0.5 neutral (90°), 1 wets completely (solids and bodies have their own `adhesion`)"),
};
// clang-format on

#undef PBF_PARAM

std::string number(double value, ParamType type) {
    std::ostringstream s;
    if (type == ParamType::Int)
        s << static_cast<long long>(value);
    else
        s << static_cast<float>(value);
    return s.str();
}

std::string interval(double lo, double hi, const ParamRange& r, ParamType type) {
    return std::string(r.loOpen ? "(" : "[") + number(lo, type) + ", " + number(hi, type) +
           (r.hiOpen ? ")" : "]");
}

double numeric(const ParamValue& v) {
    if (const float* f = std::get_if<float>(&v)) return *f;
    if (const int* i = std::get_if<int>(&v)) return *i;
    throw std::logic_error("param_table: not a number");
}

bool finite(const Vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

}  // namespace

std::span<const ParamInfo> paramTable() {
    return kTable;
}

const ParamInfo* findParam(std::string_view name) {
    for (const ParamInfo& p : kTable)
        if (p.path == name || p.attribute == name) return &p;
    return nullptr;
}

const void* groupIn(const SimulationParams& params, ParamGroup group) {
    return groupIn(const_cast<SimulationParams&>(params), group);
}

void* groupIn(SimulationParams& params, ParamGroup group) {
    switch (group) {
        case ParamGroup::Simulation:
            return &params;
        case ParamGroup::Fluid:
            return &params.fluid;
        case ParamGroup::Solver:
            return &params.solver;
        case ParamGroup::ArtificialPressure:
            return &params.solver.artificialPressure;
    }
    throw std::logic_error("param_table: unknown group");
}

std::string_view ParamInfo::name() const {
    const std::size_t dot = path.rfind('.');
    return dot == std::string_view::npos ? path : path.substr(dot + 1);
}

ParamValue ParamInfo::get(const SimulationParams& params) const {
    return getIn(groupIn(params, group));
}

void ParamInfo::set(SimulationParams& params, const ParamValue& value) const {
    setIn(groupIn(params, group), value);
}

std::string ParamInfo::check(const SimulationParams& params) const {
    const ParamValue value = get(params);
    const std::string field(path);
    switch (type) {
        case ParamType::Float:
        case ParamType::Int: {
            const double v = numeric(value);
            // A float member holds its value rounded to float: the bounds are
            // compared rounded the same way, so that a value written as the
            // bound (particle_radius 1e-5) is the bound and in range.
            const auto stored = [this](double bound) {
                return type == ParamType::Float ? double(float(bound)) : bound;
            };
            const double lo = stored(range.lo);
            const double hi = stored(range.hiParam.empty()
                                         ? range.hi
                                         : numeric(findParam(range.hiParam)->get(params)));
            if (v == range.special) return {};
            const bool above = range.loOpen ? v > lo : v >= lo;
            const bool below = range.hiOpen ? v < hi : v <= hi;
            if (above && below) return {};  // NaN fails both
            const std::string special =
                std::isnan(range.special) ? "" : " or " + number(range.special, type);
            return field + ": must be in " + interval(range.lo, hi, range, type) + special +
                   ", got " + number(v, type);
        }
        case ParamType::Vec3: {
            const Vec3 v = std::get<Vec3>(value);
            if (finite(v) && length(v) <= range.hi) return {};
            return field + ": must be finite with magnitude <= " + number(range.hi, type) + " " +
                   std::string(unit == "m/s²" ? "m/s^2" : unit);
        }
        case ParamType::Box: {
            const Aabb box = std::get<Aabb>(value);
            if (!finite(box.min) || !finite(box.max)) return field + ": coordinates must be finite";
            const Vec3 e = box.extent();
            if (!(e.x > 0 && e.y > 0 && e.z > 0))
                return field + ": max must be greater than min on every axis";
            return {};
        }
        case ParamType::Choice:
            return {};
    }
    return {};
}

std::string_view timeStepName(TimeStepMode mode) {
    return mode == TimeStepMode::Fixed ? "fixed" : "adaptive";
}

TimeStepMode parseTimeStepName(std::string_view name) {
    if (name == "adaptive") return TimeStepMode::Adaptive;
    if (name == "fixed") return TimeStepMode::Fixed;
    throw std::invalid_argument("expected \"adaptive\" or \"fixed\", got \"" + std::string(name) +
                                "\"");
}

std::string rangeText(const ParamInfo& p) {
    if (!p.rangeText.empty()) return std::string(p.rangeText);
    return interval(p.range.lo, p.range.hi, p.range, p.type);
}

std::string valueText(const ParamValue& value) {
    struct Text {
        std::string operator()(float v) const { return number(v, ParamType::Float); }
        std::string operator()(int v) const { return number(v, ParamType::Int); }
        std::string operator()(const Vec3& v) const {
            return "[" + number(v.x, ParamType::Float) + ", " + number(v.y, ParamType::Float) +
                   ", " + number(v.z, ParamType::Float) + "]";
        }
        std::string operator()(const Aabb& b) const {
            return "{\"min\": " + (*this)(b.min) + ", \"max\": " + (*this)(b.max) + "}";
        }
        std::string operator()(TimeStepMode m) const {
            return "\"" + std::string(timeStepName(m)) + "\"";
        }
    };
    return std::visit(Text{}, value);
}

std::string defaultText(const ParamInfo& p) {
    if (!p.defaultText.empty()) return std::string(p.defaultText);
    return valueText(p.get(SimulationParams{}));
}

std::string paramTableMarkdown() {
    std::string out =
        "| field | unit | default | valid range | live | meaning |\n"
        "| --- | --- | --- | --- | --- | --- |\n";
    for (const ParamInfo& p : kTable) {
        const std::string value = p.required ? "required" : "`" + defaultText(p) + "`";
        out += "| `" + std::string(p.path) + "` | " + std::string(p.unit) + " | " + value + " | " +
               rangeText(p) + " | " + (p.live ? "yes" : "no") + " | " + std::string(p.description) +
               " |\n";
    }
    return out;
}

}  // namespace pbf
