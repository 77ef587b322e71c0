// A standing wave left to itself: the first mode of a closed rectangular
// tank, started from the linear solution's velocity field, oscillates at
//   w^2 = g k tanh(k h),  k = pi / L
// (Lamb, Hydrodynamics, sec. 257) and, in water, decays at the viscous rate
// 2 nu k^2 (Lamb sec. 348), a damping ratio of order 1e-5 in this tank. The
// mode's amplitude is the least-squares projection of the particle
// velocities on the mode's velocity field; a damped oscillator fitted to it
// gives the natural frequency (checked) and the damping ratio (reported:
// PBF's own dissipation of surface waves, the quantity the sloshing, heave
// and wave-flume results depend on).
#include "validate/standing_wave.hpp"

#include <fmt/format.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "pbf/world/world.hpp"
#include "validate/measure.hpp"

namespace pbf::validation {
namespace {

using detail::StandingWave;

constexpr double kG = 9.81;
constexpr float kLength = 0.4f;       // m: the domain's x extent, the tank's length
constexpr float kDepth = 0.1f;        // m
constexpr float kHeight = 0.3f;       // m: the domain's y extent
constexpr double kAmplitude = 0.005;  // m: the surface's amplitude at the walls
constexpr double kSettle = 0.5;       // s at rest before the wave starts
constexpr double kDuration = 4.0;     // s of record, about 4.5 periods
constexpr float kFps = 60.0f;
// solver.consistent_correction of the runs reported beside the default's.
constexpr float kCorrection = 0.45f;

double wavenumber() {
    return std::numbers::pi / kLength;
}

// The mode's velocity per unit surface velocity amplitude at (x, y), y from
// the bottom: the gradient of cos(kx) cosh(ky) / sinh(kh), the phase at
// which the surface is level and the water moves fastest.
Vec3 modeVelocity(double x, double y) {
    const double k = wavenumber();
    const double s = std::sinh(k * kDepth);
    return {float(-std::sin(k * x) * std::cosh(k * y) / s),
            float(std::cos(k * x) * std::sinh(k * y) / s), 0.0f};
}

}  // namespace

namespace detail {

double standingWaveTheoryOmega() {
    const double k = wavenumber();
    return std::sqrt(kG * k * std::tanh(k * kDepth));
}

StandingWave standingWave(float radius, float consistentCorrection, double duration) {
    WorldDef def;
    def.name = "standing_wave";
    // Four particles across: the domain's walls are free slip, so a thin
    // tank carries the two-dimensional mode at a quarter of the cost.
    const float width = 8.0f * radius;
    def.simulation.domain = {{0, 0, 0}, {kLength, kHeight, width}};
    def.simulation.particleRadius = radius;
    def.simulation.solver.consistentCorrection = consistentCorrection;
    def.fluidBlocks.push_back({{{0, 0, 0}, {kLength, kDepth, width}}, {0, 0, 0}});
    def.fps = kFps;
    World world(def);
    while (world.time() < kSettle - 1e-9) detail::step(world);

    // Surface velocity amplitude a w for a surface amplitude a.
    const double speed = kAmplitude * standingWaveTheoryOmega();
    auto project = [&](const ParticleArrays& a) {
        double along = 0.0, norm = 0.0;
        for (std::size_t i = 0; i < a.count; ++i) {
            const std::vector<float>& x = *a.position;
            const std::vector<float>& v = *a.velocity;
            const Vec3 m = modeVelocity(x[3 * i], x[3 * i + 1]);
            along += double(v[3 * i]) * m.x + double(v[3 * i + 1]) * m.y;
            norm += double(m.x) * m.x + double(m.y) * m.y;
        }
        return along / norm / speed;
    };
    {
        ParticleArrays& a = world.arraysById();
        std::vector<float>& x = *a.position;
        std::vector<float>& v = *a.velocity;
        for (std::size_t i = 0; i < a.count; ++i) {
            const Vec3 m = modeVelocity(x[3 * i], x[3 * i + 1]) * float(speed);
            v[3 * i] = m.x;
            v[3 * i + 1] = m.y;
            v[3 * i + 2] = 0.0f;
        }
    }
    StandingWave d;
    d.radius = radius;
    d.consistentCorrection = consistentCorrection;
    d.particles = world.particleCount();
    const double start = world.time();
    while (world.time() - start < duration - 1e-9) {
        detail::step(world);
        d.t.push_back(world.time() - start);
        d.amplitude.push_back(project(world.arraysById()));
    }
    d.fit = detail::fitDampedOscillator(d.t, d.amplitude);
    d.omega = 2.0 * std::numbers::pi / d.fit.naturalPeriod;
    return d;
}

}  // namespace detail

namespace {

StandingWave decay(float radius, float consistentCorrection, const Options& options) {
    StandingWave d = detail::standingWave(radius, consistentCorrection, kDuration);
    if (options.progress)
        options.progress(fmt::format(
            "standing_wave: radius {} m, consistent_correction {}: w = {:.3f} rad/s ({:+.1f} %), "
            "damping ratio {:.3f}",
            radius, consistentCorrection, d.omega,
            100.0 * (d.omega / detail::standingWaveTheoryOmega() - 1.0), d.fit.dampingRatio));
    return d;
}

CaseResult run(const Options& options) {
    CaseResult result;
    result.name = "standing_wave";
    result.title = "A standing wave in a closed tank: frequency and decay";
    const double omega = detail::standingWaveTheoryOmega();
    const std::vector<float> radii = options.quick ? std::vector<float>{0.005f, 0.0025f}
                                                   : std::vector<float>{0.005f, 0.0025f, 0.00125f};
    std::vector<StandingWave> runs, corrected;
    for (const float r : radii) runs.push_back(decay(r, 0.0f, options));
    for (const float r : {0.005f, 0.0025f}) corrected.push_back(decay(r, kCorrection, options));

    plot::Panel panel{"The mode's velocity amplitude", "t (s)", "amplitude / start", {}};
    for (const std::vector<StandingWave>* set : {&runs, &corrected})
        for (const StandingWave& d : *set)
            panel.series.push_back(
                detail::record(result, detail::runLabel(d.radius, d.consistentCorrection), "t_s",
                               d.t, "amplitude", d.amplitude));
    result.figure = {result.title, {panel}, 1};

    const StandingWave& fine = runs.back();
    result.checks.push_back(
        {fmt::format("natural angular frequency (r = {:g} mm)", 1e3 * fine.radius), fine.omega,
         omega, 0.1 * omega, "rad/s",
         "w^2 = g k tanh(k h), k = pi / L (Lamb, Hydrodynamics, sec. 257)",
         "10 %: as the shaken tank's sweep resolves its resonance; the error here falls with "
         "the particle size (see the table) and is not the fit's (its standard error "
         "is under 1 %)"});
    Convergence study{"|w / w(linear theory) - 1|", "particle radius (mm)", {}, {}};
    for (const StandingWave& d : runs) {
        study.h.push_back(1e3 * d.radius);
        study.error.push_back(std::fabs(d.omega / omega - 1.0));
    }
    result.checks.push_back(
        convergenceCheck(study,
                         "the frequency must approach linear theory as the particles "
                         "shrink"));
    result.convergence.push_back(std::move(study));

    std::string rows;
    for (const std::vector<StandingWave>* set : {&runs, &corrected})
        for (const StandingWave& d : *set)
            rows += fmt::format(
                "| {:g} | {:g} | {} | {:.3f} ({:+.1f} %) | {:.4f} | {:.3f} | {:.3f} |\n",
                1e3 * d.radius, d.consistentCorrection, d.particles, d.omega,
                100.0 * (d.omega / omega - 1.0),
                2.0 * std::numbers::pi * d.fit.naturalPeriodError /
                    (d.fit.naturalPeriod * d.fit.naturalPeriod),
                d.fit.dampingRatio, d.fit.rms);
    result.notes = fmt::format(
        "A tank {} m long, filled {} m deep (the domain's free-slip walls; four particles "
        "across), rests {} s; then the particles take the first mode's velocity field for a "
        "surface amplitude of {} mm, and the projection of their velocities on the mode is "
        "recorded for {} s. Linear theory: w = {:.3f} rad/s (T = {:.4f} s). A damped "
        "oscillator fitted to the record gives the natural frequency and the damping ratio "
        "(water's own: 2 nu k^2 / w = {:.1e}). The rows with solver.consistent_correction {:g} "
        "are reported, not checked.\n\n"
        "| r (mm) | consistent_correction | particles | w (rad/s) | standard error | damping "
        "ratio | fit RMS |\n"
        "| --- | --- | --- | --- | --- | --- | --- |\n{}",
        kLength, kDepth, kSettle, 1e3 * kAmplitude, kDuration, omega,
        2.0 * std::numbers::pi / omega, 2.0 * 1e-6 * wavenumber() * wavenumber() / omega,
        kCorrection, rows);
    return result;
}

}  // namespace

Case standingWaveCase() {
    return {"standing_wave", "a standing wave's frequency against linear theory, its decay", run};
}

}  // namespace pbf::validation
