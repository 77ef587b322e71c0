// Free fall: a block of water falling through an empty domain follows
// y(t) = y0 - g t^2 / 2 and v(t) = -g t. Nothing touches it, its density
// constraint is at rest (interior particles at rho0, the surface clamped),
// and every pair correction is equal and opposite, so its centre of mass
// moves exactly as the integrator moves one particle: symplectic Euler,
// v += g dt; x += v dt, whose position error is g t dt / 2 (first order)
// and whose velocity is exact. Three fixed step sizes show the order.
#include <fmt/format.h>

#include <cmath>

#include "pbf/world/world.hpp"
#include "validate/measure.hpp"

namespace pbf::validation {
namespace {

constexpr double kDuration = 1.0;  // s: the block falls 4.9 m
constexpr float kFps = 60.0f;

struct Fall {
    double dt = 0.0;
    int steps = 0;
    std::vector<double> t, drop, velocity;  // centre of mass: y0 - y, v_y
    std::vector<double> height;             // the block's extent in y, m
};

double extentY(const ParticleStore& p) {
    float lo = 1e30f, hi = -1e30f;
    for (float y : p.position.y) {
        lo = std::min(lo, y);
        hi = std::max(hi, y);
    }
    return double(hi - lo);
}

Fall fall(int substeps, float radius) {
    WorldDef def;
    def.name = "free_fall";
    def.simulation.domain = {{-0.5f, -6.0f, -0.5f}, {0.5f, 0.5f, 0.5f}};
    def.simulation.particleRadius = radius;
    def.fluidBlocks.push_back({{{-0.05f, 0.2f, -0.05f}, {0.05f, 0.3f, 0.05f}}, {0, 0, 0}});
    def.fps = kFps;
    def.simulation.solver.timeStepMode = TimeStepMode::Fixed;
    def.simulation.solver.fixedSubsteps = substeps;
    World world(def);
    const auto centre = [&] {
        const ParticleStore& p = world.particles();
        double y = 0.0, v = 0.0;
        for (std::size_t i = 0; i < p.size(); ++i) {
            y += p.position.y[i];
            v += p.velocity.y[i];
        }
        return std::pair{y / double(p.size()), v / double(p.size())};
    };
    Fall f;
    f.dt = 1.0 / (double(kFps) * substeps);
    const double y0 = centre().first;
    f.t.push_back(0.0);
    f.drop.push_back(0.0);
    f.velocity.push_back(0.0);
    f.height.push_back(extentY(world.particles()));
    while (world.time() < kDuration - 1e-9) {
        f.steps += detail::step(world).substeps;
        const auto [y, v] = centre();
        f.t.push_back(world.time());
        f.drop.push_back(y0 - y);
        f.velocity.push_back(v);
        f.height.push_back(extentY(world.particles()));
    }
    return f;
}

CaseResult run(const Options& options) {
    CaseResult result;
    result.name = "free_fall";
    result.title = "Free fall of a block of water against y = y0 - g t^2/2";
    const double g = 9.81;
    const float radius = options.quick ? 0.01f : 0.005f;
    const std::vector<int> substeps{2, 4, 8};  // dt = 1/120, 1/240, 1/480 s
    std::vector<Fall> falls;
    for (int s : substeps) {
        if (options.progress)
            options.progress(fmt::format("free_fall: dt = 1/{:.0f} s", kFps * float(s)));
        falls.push_back(fall(s, radius));
    }
    plot::Panel drop{"Drop of the centre of mass", "t (s)", "drop y0 - y (m)", {}};
    plot::Panel error{"Drop minus the closed form g t^2 / 2", "t (s)", "error (mm)", {}};
    plot::Panel height{
        "Height of the block (s_corr pushes its surface out)", "t (s)", "extent in y (m)", {}};
    std::vector<double> closed, finalErrors;
    for (double t : falls.front().t) closed.push_back(0.5 * g * t * t);
    drop.series.push_back(detail::record(result, "closed form g t^2/2", "t_s", falls.front().t,
                                         "drop_m", closed, plot::Style::Dashed));
    for (const Fall& f : falls) {
        std::vector<double> e;
        for (std::size_t k = 0; k < f.t.size(); ++k)
            e.push_back(1e3 * (f.drop[k] - 0.5 * g * f.t[k] * f.t[k]));
        const std::string label = fmt::format("dt = 1/{:.0f} s", 1.0 / f.dt);
        drop.series.push_back(detail::record(result, label, "t_s", f.t, "drop_m", f.drop));
        error.series.push_back(detail::record(result, label + " error", "t_s", f.t, "error_mm", e));
        height.series.push_back(
            detail::record(result, label + " height", "t_s", f.t, "m", f.height));
        finalErrors.push_back(f.drop.back() - 0.5 * g * kDuration * kDuration);
    }
    result.figure = {result.title, {drop, error, height}, 2};

    const Fall& fine = falls.back();
    const double t = fine.t.back();
    // Rounding: v = (x* - x) / dt of float positions of ~5 m errs by ~5e-7 m / dt
    // per step and the errors add up in the position; tests/world/physics_test
    // bounds it by 3e-6 m per step (measured: 0.5 mm after 480 steps).
    const double rounding = 3e-6 * fine.steps;
    result.checks.push_back(
        {fmt::format("drop at t = {:.0f} s, dt = 1/{:.0f} s", t, 1.0 / fine.dt), fine.drop.back(),
         0.5 * g * t * t, 0.5 * g * t * fine.dt * 1.01 + rounding, "m", "closed form g t^2 / 2",
         "symplectic Euler's position error g t dt / 2 (first order in dt), plus float rounding "
         "of 3e-6 m per step"});
    result.checks.push_back(
        {fmt::format("velocity at t = {:.0f} s", t), fine.velocity.back(), -g * t, 0.01, "m/s",
         "closed form -g t",
         "exact in symplectic Euler; v = (x* - x) / dt of float positions adds ~3e-4 m/s of "
         "rounding per step, a random walk of ~0.007 m/s over 480 steps"});
    const double order = std::log2(finalErrors[0] / finalErrors[1]);
    result.checks.push_back(
        {"order of the error (dt 1/120 -> 1/240 s)", order, 1.0, 0.05, "",
         "symplectic Euler is first order",
         "the error g t dt / 2 halves with dt; 0.05 allows the rounding (taken between the two "
         "larger steps, where rounding is smallest against the error)"});
    result.notes = fmt::format(
        "A {:.0f} cm cube of water ({} particles across, radius {} m) falls for {:.0f} s "
        "through an empty domain with fixed steps dt = 1/120, 1/240 and 1/480 s. Measured: the "
        "mean position and velocity of its particles. Error at t = 1 s: {:.2f}, {:.2f} and "
        "{:.2f} mm (the bound g t dt / 2 is {:.1f}, {:.1f} and {:.1f} mm).\n\n"
        "Not a check, but visible in the third plot: the block does not stay a block. PBF's "
        "artificial pressure s_corr (k = 0.01) pushes neighbours apart and, at a free surface "
        "where the clamped constraint does not pull back, drives the surface particles "
        "outwards; the block's height grows at {:.3f}, {:.3f} and {:.3f} m/s for the three steps "
        "(the push is per step, so it grows as dt shrinks; with k = 0 the block keeps its "
        "shape). The centre of mass is unaffected: the push is symmetric.",
        10.0, int(std::lround(0.1 / (2 * radius))), radius, kDuration, 1e3 * finalErrors[0],
        1e3 * finalErrors[1], 1e3 * finalErrors[2], 1e3 * 0.5 * g * falls[0].dt,
        1e3 * 0.5 * g * falls[1].dt, 1e3 * 0.5 * g * falls[2].dt,
        (falls[0].height.back() - falls[0].height.front()) / kDuration,
        (falls[1].height.back() - falls[1].height.front()) / kDuration,
        (falls[2].height.back() - falls[2].height.front()) / kDuration);
    return result;
}

}  // namespace

Case freeFallCase() {
    return {"free_fall", "free fall of a block against y0 - g t^2/2 (closed form), three dt", run};
}

}  // namespace pbf::validation
