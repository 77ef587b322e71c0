// An open channel: water fed at a fixed flow rate through an inlet, over a
// weir, out through an outlet (scenes/open_channel.json). Three things a
// channel that runs for minutes must get right:
//   * the water balances exactly: particles stored = the fluid block's +
//     emitted - removed, every frame (nothing lost, nothing made);
//   * the flow becomes steady: what leaves through the outlet equals what
//     the inlet feeds;
//   * the level upstream is the weir's: the flow over it passes through
//     critical depth, y_c = (q^2 / g)^(1/3) for the discharge per width q,
//     and the head above a broad crest is H = 3/2 y_c (Henderson, Open
//     Channel Flow, 1966, sec. 6.5). The crest here is short (6 cm against
//     a 9 cm head): a sharp-crested weir's discharge coefficient (Rehbock:
//     C_d = 0.611 + 0.08 H / P) gives a head 12 % lower, which sets the
//     tolerance.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "pbf/world/world.hpp"
#include "validate/measure.hpp"

namespace pbf::validation {
namespace {

constexpr double kG = 9.81;
constexpr float kWidth = 0.2f;        // m: the channel (the domain's z extent)
constexpr float kWeirHeight = 0.08f;  // m: P
constexpr float kFlowRate = 0.01f;    // m^3/s: 10 L/s, q = 0.05 m^2/s
constexpr float kOutletX = 1.9f;      // m: water past it leaves
// The level is read in the pool 0.3-0.5 m before the weir, away from the
// inlet's plunge and the drawdown over the crest.
constexpr float kGaugeFrom = 0.5f, kGaugeTo = 0.7f;

WorldDef channel(float radius) {
    WorldDef def;
    def.name = "open_channel";
    def.simulation.domain = {{0, 0, 0}, {2.0f, 0.4f, kWidth}};
    def.simulation.particleRadius = radius;
    def.fluidBlocks.push_back({{{0.05f, 0, 0}, {1.0f, kWeirHeight, kWidth}}, {}});
    SolidDescription weir;
    weir.kind = SolidDescription::Kind::Box;
    weir.box = {{1.0f, 0, 0}, {1.06f, kWeirHeight, kWidth}};
    def.solids.push_back(weir);
    // The inlet pours down over the channel's whole width above its
    // upstream end (the new particles land in air). Its stream falls onto
    // the pool: a stream along the channel would bring its momentum, and
    // the pool before the weir would not be still.
    EmitterDescription inlet;
    inlet.position = {0.08f, 0.27f, 0.5f * kWidth};
    inlet.direction = {0, -1, 0};
    inlet.width = 0.1f;     // along the channel (a vertical stream's width is along x)
    inlet.height = kWidth;  // across it
    inlet.flowRate = kFlowRate;
    def.emitters.push_back(inlet);
    OutletDescription outlet;
    outlet.region.kind = OutletRegion::Kind::HalfSpace;
    outlet.region.point = {kOutletX, 0, 0};
    outlet.region.normal = {1, 0, 0};
    def.outlets.push_back(outlet);
    def.fps = 30.0f;
    return def;
}

// Depth of the pool between kGaugeFrom and kGaugeTo: the particles' water,
// (2 r)^3 each at rest density, over the gauge's area.
double poolDepth(const World& world) {
    const ParticleStore& p = world.particles();
    const double spacing = 2.0 * double(world.settings().particleRadius);
    std::size_t inside = 0;
    for (std::size_t i = 0; i < p.size(); ++i)
        if (p.position.x[i] > kGaugeFrom && p.position.x[i] < kGaugeTo) ++inside;
    return double(inside) * spacing * spacing * spacing / (double(kGaugeTo - kGaugeFrom) * kWidth);
}

struct Run {
    float radius = 0.0f;
    std::vector<double> t, stored, outflow, inflow, depth;  // outflow, inflow in L/s per frame
    long long worstImbalance = 0;  // largest |stored - (initial + emitted - removed)|
    double outflowShare = 0.0;     // outflow / inflow over the last kSteady seconds
    double head = 0.0;             // mean depth over the weir's crest in that time, m
    std::size_t initial = 0, emitted = 0, removed = 0;
};

constexpr double kSteady = 3.0;  // s: the last seconds, after the channel has filled

Run flow(float radius, double duration, const Options& options) {
    World world(channel(radius));
    Run run;
    run.radius = radius;
    run.initial = world.particleCount();
    const double particleLitres = 1e3 * std::pow(2.0 * double(radius), 3.0);
    const double frameDt = world.frameDuration();
    std::size_t emittedSteady = 0, removedSteady = 0;
    std::vector<double> steadyDepth;
    while (world.time() < duration - 1e-9) {
        const FrameReport r = detail::step(world);
        run.emitted += r.emitted;
        run.removed += r.removed;
        const long long expected =
            static_cast<long long>(run.initial + run.emitted) - static_cast<long long>(run.removed);
        run.worstImbalance =
            std::max(run.worstImbalance,
                     std::llabs(static_cast<long long>(world.particles().size()) - expected));
        run.t.push_back(world.time());
        run.stored.push_back(double(world.particleCount()) * particleLitres);
        run.outflow.push_back(double(r.removed) * particleLitres / frameDt);
        run.inflow.push_back(double(r.emitted) * particleLitres / frameDt);
        run.depth.push_back(poolDepth(world));
        if (world.time() > duration - kSteady + 1e-9) {
            emittedSteady += r.emitted;
            removedSteady += r.removed;
            steadyDepth.push_back(run.depth.back());
        }
    }
    run.outflowShare = double(removedSteady) / double(std::max<std::size_t>(1, emittedSteady));
    run.head = detail::sampleMean(steadyDepth).mean - kWeirHeight;
    if (options.progress)
        options.progress(fmt::format(
            "open_channel: radius {} m: {} + {} emitted - {} removed = {} particles at {:.1f} s; "
            "outflow / inflow over the last {:.0f} s {:.4f}, head over the weir {:.4f} m",
            radius, run.initial, run.emitted, run.removed, world.particleCount(), world.time(),
            kSteady, run.outflowShare, run.head));
    return run;
}

// 1.5 s means of a per-frame rate (the outlet takes particles in bursts).
std::vector<double> smoothed(const std::vector<double>& rate, std::size_t frames) {
    std::vector<double> out(rate.size(), 0.0);
    for (std::size_t k = 0; k < rate.size(); ++k) {
        const std::size_t from = k + 1 >= frames ? k + 1 - frames : 0;
        double sum = 0.0;
        for (std::size_t j = from; j <= k; ++j) sum += rate[j];
        out[k] = sum / double(k + 1 - from);
    }
    return out;
}

CaseResult run(const Options& options) {
    CaseResult result;
    result.name = "open_channel";
    result.title = "Open channel: inlet, weir and outlet";
    const std::vector<float> radii =
        options.quick ? std::vector<float>{0.01f} : std::vector<float>{0.01f, 0.00707f};
    const double duration = options.quick ? 7.0 : 10.0;
    std::vector<Run> runs;
    for (const float r : radii) runs.push_back(flow(r, duration, options));

    const double q = double(kFlowRate) / kWidth;
    const double critical = std::cbrt(q * q / kG);
    const double broadCrested = 1.5 * critical;

    plot::Panel rates{"Inflow and outflow (1.5 s means)", "t (s)", "flow (L/s)", {}};
    plot::Panel stored{"Water in the channel", "t (s)", "volume (L)", {}};
    plot::Panel depth{"Pool depth 0.3-0.5 m before the weir", "t (s)", "depth (m)", {}};
    for (const Run& run : runs) {
        const std::string label = fmt::format("r = {:g} mm", 1e3 * run.radius);
        rates.series.push_back(detail::record(result, "outflow, " + label, "t_s", run.t,
                                              "litres_per_s", smoothed(run.outflow, 45)));
        rates.series.push_back(detail::record(result, "inflow, " + label, "t_s", run.t,
                                              "litres_per_s", smoothed(run.inflow, 45),
                                              plot::Style::Dashed));
        stored.series.push_back(
            detail::record(result, "stored, " + label, "t_s", run.t, "litres", run.stored));
        depth.series.push_back(
            detail::record(result, "depth, " + label, "t_s", run.t, "m", run.depth));
    }
    depth.series.push_back(detail::record(
        result, "weir + 3/2 y_c (broad crest)", "t_s", {runs.front().t.front(), duration}, "m",
        {kWeirHeight + broadCrested, kWeirHeight + broadCrested}, plot::Style::Dashed));
    result.figure = {result.title, {rates, stored, depth}, 3};

    long long worst = 0;
    for (const Run& run : runs) worst = std::max(worst, run.worstImbalance);
    result.checks.push_back(
        {"particles stored - (initial + emitted - removed), largest over every frame",
         double(worst), 0.0, 0.0, "", "counting: water is neither lost nor made",
         "exact: the outlet removes whole particles and the inlet adds whole particles; any "
         "difference is a particle lost or duplicated by a backend",
         Check::Bound::AtMost});
    const Run& fine = runs.back();
    result.checks.push_back(
        {fmt::format("outflow / inflow over the last {:.0f} s (r = {:g} mm)", kSteady,
                     1e3 * fine.radius),
         fine.outflowShare, 1.0, 0.05, "", "a steady flow: what comes in goes out",
         "the water stored still changes a little in 3 s (the pool's sloshing and the outlet's "
         "bursts: 0.2-2.5 % of what flows through, measured); a channel still filling or "
         "draining shows as more"});
    result.checks.push_back(
        {fmt::format("head over the weir (r = {:g} mm)", 1e3 * fine.radius), fine.head,
         broadCrested, 0.15 * broadCrested, "m",
         fmt::format("H = 3/2 (q^2 / g)^(1/3), q = {:.3f} m^2/s (critical depth over a broad "
                     "crest)",
                     q),
         "the crest is short for its head (6 cm against 9 cm): a sharp-crested weir (Rehbock's "
         "discharge coefficient 0.611 + 0.08 H / P) needs a head 12 % lower; the tolerance "
         "spans both limits"});
    std::string rows;
    for (const Run& run : runs)
        rows += fmt::format("| {:g} | {} | {} | {} | {} | {:.4f} | {:.4f} |\n", 1e3 * run.radius,
                            run.initial, run.emitted, run.removed,
                            run.initial + run.emitted - run.removed, run.outflowShare, run.head);
    result.notes = fmt::format(
        "A channel 2 m long and {w} m wide fed {Q:g} L/s over its width from above its upstream "
        "end (a rectangular emitter with `flow_rate`), over a {P} m weir, out through a plane "
        "outlet at x = {x} m, followed for {T:g} s. Outflow and inflow are counted in "
        "particles (each (2 r)^3 of water) per frame; the depth from the particles between "
        "x = {a} and {b} m.\n\n"
        "| r (mm) | initial | emitted | removed | stored at the end | outflow / inflow, last "
        "{s:.0f} s | head (m) |\n| --- | --- | --- | --- | --- | --- | --- |\n{rows}",
        fmt::arg("w", kWidth), fmt::arg("Q", 1e3 * kFlowRate), fmt::arg("P", kWeirHeight),
        fmt::arg("x", kOutletX), fmt::arg("T", duration), fmt::arg("a", kGaugeFrom),
        fmt::arg("b", kGaugeTo), fmt::arg("s", kSteady), fmt::arg("rows", rows));
    return result;
}

}  // namespace

Case openChannelCase() {
    return {"open_channel", "a channel fed through an inlet, over a weir, out through an outlet",
            run};
}

}  // namespace pbf::validation
