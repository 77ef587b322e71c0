// Collapse of a water column, after Martin & Moyce 1952 (data and source in
// martin_moyce_data.hpp): a column a wide and 2a high (n^2 = 2, a = 2.25 in)
// stands against the back wall of a long tank and is released at t = 0.
// Compared: the surge front Z = x / a against T = n t sqrt(g / a) (their
// Table 2) and the residual height of the column at the back wall
// H = eta / (n^2 a) against tau = t sqrt(g / a) (Table 6), at three
// resolutions.
//
// The flow is two-dimensional: the tank is 4 particle layers deep between
// free-slip side walls. The simulated column is released instantly; the
// experiment's front starts late against its clock. One constant delay
// (dT in [0, 0.5]) is fitted to the front and reported and checked. A
// gate lifted at the speed of an instantaneous dam break (Lauber & Hager's
// criterion, kGateSpeed) was tried as the cause of that delay:
// its raw front is no closer to the experiment than the instant release's
// (RMS 0.295 against 0.290 at 30 across a: the water squeezed under the
// rising gate leaves as a fast jet along the floor, so the front does not
// start later), so it does not explain the delay; one run with it is
// reported beside the others. What the raw front's lead is: the simulated
// surge matches the experiment's front at T = 0.41 and then runs ahead by a
// tongue of water thinner than about 10 mm (0.18 a) at every resolution
// (reported: the simulated depth where the experiment saw its front): the
// lead is a thin tongue along the floor, not a late start of the whole
// surge. One run with water's surface tension is reported too. A wall
// function for the floor's bed resistance (shear 1/2 rho C_f |u| u) at a
// smooth bed's C_f shortens the lead by 0.02-0.04 only and it still grows
// with resolution (docs/validation.md, "Bed resistance, tried").
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <vector>

#include "pbf/world/world.hpp"
#include "validate/martin_moyce_data.hpp"
#include "validate/measure.hpp"

namespace pbf::validation {
namespace {

namespace mm = martin_moyce;

constexpr double kG = 9.81;
constexpr double kTankLength = 14.0;  // in a: the front reaches ~10 a by tau = 5.25
constexpr double kLastTau = 5.25;     // the last row of Table 6 that the tank length allows
constexpr double kMaxDelay = 0.5;     // largest gate delay fitted, in T
// A gate lifted through the column's height h0 = 2a within sqrt(2 h0 / g),
// the opening time up to which dam-break experiments count a gate's
// removal as instantaneous (Lauber & Hager 1998, "Experiments to dambreak
// wave: horizontal channel", J. Hydraulic Res. 36(3) 291-307; the
// criterion as Ye et al. 2020, Energies 13(23) 6280, apply it): speed
// h0 / sqrt(2 h0 / g) = sqrt(g h0 / 2) = 0.75 m/s. How Martin & Moyce
// released their column we could not read (the paper is paywalled).
const double kGateSpeed =
    std::sqrt(kG * martin_moyce::kHeightRatio * martin_moyce::kColumnWidth / 2.0);
// Water's surface tension at 20 deg C (N/m; Vargaftik, Volkov & Voljak
// 1983, J. Phys. Chem. Ref. Data 12(3) 817): the experiment's water had it,
// pbf's default fluid has none. One run with it is reported: the
// simulated surge runs ahead of the experiment's by a tongue about 10 mm
// deep, four capillary lengths sqrt(sigma / (rho g)) = 2.7 mm, where
// capillarity is no longer negligible against gravity.
constexpr float kWaterSurfaceTension = 0.0728f;
constexpr float kGateFps = 2000.0f;     // with the gate: frames of 0.5 ms (it moves between frames)
constexpr double kSampleEvery = 0.004;  // s: the front and the height every 4 ms

struct Collapse {
    int across = 0;               // particles across the column width a
    double gateSpeed = 0.0;       // m/s; 0: released instantly
    float surfaceTension = 0.0f;  // N/m (fluid.surface_tension)
    std::size_t particles = 0;
    std::vector<double> T, Z, tau, H;  // per frame
    // Per frame, the depth of the water (m) in strips one spacing (2r) wide
    // along the tank: the top of the highest particle with at least half the
    // rest density in the strip, 0 where there is none.
    double stripWidth = 0.0;
    std::vector<std::vector<float>> depth;
};

// `gateSpeed` > 0: the column stands behind a gate (a plate a / 10 thick,
// the tank's height and depth) lifted from t = 0 at that speed.
// `surfaceTension`: the fluid's (N/m, 0: none, pbf's default).
Collapse collapse(int across, double gateSpeed, float surfaceTension, const Options& options) {
    const double a = mm::kColumnWidth;
    const float r = float(a / (2.0 * across));
    const float depth = 4.0f * 2.0f * r;
    const float tankHeight = float(2.5 * a);
    WorldDef def;
    def.name = "martin_moyce";
    def.simulation.domain = {{0, 0, 0}, {float(kTankLength * a), tankHeight, depth}};
    def.simulation.particleRadius = r;
    def.simulation.fluid.surfaceTension = surfaceTension;
    def.fluidBlocks.push_back(
        {{{0, 0, 0}, {float(a), float(mm::kHeightRatio * a), depth}}, {0, 0, 0}});
    const bool gated = gateSpeed > 0.0;
    if (gated) {
        SolidDescription gate;
        gate.kind = SolidDescription::Kind::Box;
        // Its face a twentieth of a radius beyond the column: at exactly one
        // radius from the last lattice column, rounding left that column out.
        gate.box = {{float(a) + 0.05f * r, 0.0f, 0.0f}, {float(1.1 * a), tankHeight, depth}};
        def.solids.push_back(gate);
    }
    def.fps = gated ? kGateFps : float(1.0 / kSampleEvery);  // samples dT = 0.074 apart
    World world(def);
    Collapse c;
    c.across = across;
    c.gateSpeed = gateSpeed;
    c.surfaceTension = surfaceTension;
    c.particles = world.particleCount();
    c.stripWidth = 2.0 * r;
    const std::size_t strips = std::size_t(std::ceil(kTankLength * a / c.stripWidth)) + 1;
    const double n = std::sqrt(mm::kHeightRatio);
    const double rate = std::sqrt(kG / a);
    const float halfRho0 = 0.5f * def.simulation.fluid.restDensity;
    const auto measure = [&] {
        const ParticleStore& p = world.particles();
        // The front: the farthest particle with at least half the rest
        // density (a lone droplet ahead of the surge has about 20 %), plus
        // its radius. The height: the highest such particle in the first
        // lattice column at the back wall, plus its radius.
        float front = 0.0f, height = 0.0f;
        std::vector<float> profile(strips, 0.0f);
        for (std::size_t i = 0; i < p.size(); ++i) {
            if (p.density[i] < halfRho0) continue;
            front = std::max(front, p.position.x[i]);
            if (p.position.x[i] < 2.0f * r) height = std::max(height, p.position.y[i]);
            const auto strip =
                std::min(strips - 1, std::size_t(std::max(0.0f, p.position.x[i]) / c.stripWidth));
            profile[strip] = std::max(profile[strip], p.position.y[i] + r);
        }
        c.depth.push_back(std::move(profile));
        c.T.push_back(n * world.time() * rate);
        c.Z.push_back((front + r) / a);
        c.tau.push_back(world.time() * rate);
        c.H.push_back((height + r) / (mm::kHeightRatio * a));
    };
    measure();
    const int framesPerSample = int(std::lround(kSampleEvery * double(def.fps)));
    const double cleared = tankHeight / std::max(gateSpeed, 1e-9);  // s: the gate leaves the tank
    while (world.time() * rate < kLastTau + 0.05) {
        if (gated) {  // where the gate is in the middle of the coming frame
            const double middle = world.time() + 0.5 / double(def.fps);
            SolidMotion motion;
            motion.pose.position = {0.0f, float(gateSpeed * std::min(middle, cleared)), 0.0f};
            motion.velocity = {0.0f, middle < cleared ? float(gateSpeed) : 0.0f, 0.0f};
            world.setSolidMotion(0, motion);
        }
        detail::step(world);
        if (world.frame() % framesPerSample == 0) measure();
    }
    if (options.progress)
        options.progress(fmt::format(
            "martin_moyce: {} particles across a ({} particles){}{} done", across, c.particles,
            gated ? fmt::format(", gate at {:.2f} m/s", gateSpeed) : "",
            surfaceTension > 0.0f ? fmt::format(", surface tension {} N/m", surfaceTension) : ""));
    return c;
}

// Simulated values at the table's abscissae delayed by `delay`.
std::vector<double> delayed(const std::vector<double>& x, const std::vector<double>& y,
                            const double* at, std::size_t count, double delay) {
    std::vector<double> out;
    for (std::size_t k = 0; k < count; ++k) out.push_back(detail::interpolate(x, y, at[k] - delay));
    return out;
}

double rmsDifference(const std::vector<double>& a, const double* b) {
    std::vector<double> d;
    for (std::size_t k = 0; k < a.size(); ++k) d.push_back(a[k] - b[k]);
    return detail::rms(d);
}

// The gate delay dT in [0, kMaxDelay] (steps of 0.01) that best fits the front.
double fitDelay(const Collapse& c) {
    double best = 0.0, bestRms = std::numeric_limits<double>::infinity();
    for (int k = 0; k <= int(kMaxDelay * 100); ++k) {
        const double delay = 0.01 * k;
        const double e = rmsDifference(
            delayed(c.T, c.Z, mm::kFrontT.data(), mm::kFrontT.size(), delay), mm::kFrontZ.data());
        if (e < bestRms) {
            bestRms = e;
            best = delay;
        }
    }
    return best;
}

// Table 6 rows up to kLastTau.
std::size_t heightRows() {
    return std::size_t(std::count_if(mm::kHeightTau.begin(), mm::kHeightTau.end(),
                                     [](double t) { return t <= kLastTau + 1e-9; }));
}

// The simulated depth of the water (m) where the experiment saw its front:
// at each row of Table 2, the depth at x = Z a, linearly between the frames
// on either side of T (NaN outside the run). Where the simulated front runs
// ahead of the experiment's, the water ahead of that point is a tongue
// thinner than this depth.
std::vector<double> depthAtMeasuredFront(const Collapse& c) {
    std::vector<double> out;
    for (std::size_t k = 0; k < mm::kFrontT.size(); ++k) {
        const auto next = std::upper_bound(c.T.begin(), c.T.end(), mm::kFrontT[k]);
        if (next == c.T.begin() || next == c.T.end()) {
            out.push_back(std::numeric_limits<double>::quiet_NaN());
            continue;
        }
        const auto j = std::size_t(next - c.T.begin()) - 1;
        const double w = (mm::kFrontT[k] - c.T[j]) / (c.T[j + 1] - c.T[j]);
        const auto strip = std::min(c.depth[j].size() - 1,
                                    std::size_t(mm::kFrontZ[k] * mm::kColumnWidth / c.stripWidth));
        out.push_back((1.0 - w) * c.depth[j][strip] + w * c.depth[j + 1][strip]);
    }
    return out;
}

double median(std::vector<double> values) {
    std::erase_if(values, [](double v) { return std::isnan(v); });
    if (values.empty()) return std::numeric_limits<double>::quiet_NaN();
    std::sort(values.begin(), values.end());
    const std::size_t m = values.size() / 2;
    return values.size() % 2 ? values[m] : 0.5 * (values[m - 1] + values[m]);
}

struct Comparison {
    double delay = 0.0;             // fitted gate delay, in T
    double frontRms = 0.0;          // Z, after the delay
    double frontRmsRaw = 0.0;       // Z, as simulated (no delay)
    double frontSpeed = 0.0;        // dZ/dT fitted over T >= 2.2
    double heightRms = 0.0;         // H, as simulated
    double heightRmsDelayed = 0.0;  // H, after the front's delay (in tau: dT / n)
    std::vector<double> frontAtTable;
    std::vector<double> depthAtFront;  // m, per row of Table 2 (depthAtMeasuredFront)
    double medianDepthAtFront = 0.0;   // m
};

// dZ/dT of the last rows of Table 2 (T >= 2.2, where the surge runs at a
// steady speed) fitted to the simulated front over the same interval.
double frontSpeed(const std::vector<double>& T, const std::vector<double>& Z) {
    std::vector<double> x, y;
    for (std::size_t k = 0; k < T.size(); ++k)
        if (T[k] >= 2.2 && T[k] <= mm::kFrontT.back()) {
            x.push_back(T[k]);
            y.push_back(Z[k]);
        }
    return detail::fitLine(x, y).slope;
}

Comparison compare(const Collapse& c) {
    Comparison r;
    r.delay = fitDelay(c);
    r.frontAtTable = delayed(c.T, c.Z, mm::kFrontT.data(), mm::kFrontT.size(), r.delay);
    r.frontRms = rmsDifference(r.frontAtTable, mm::kFrontZ.data());
    r.frontRmsRaw = rmsDifference(delayed(c.T, c.Z, mm::kFrontT.data(), mm::kFrontT.size(), 0.0),
                                  mm::kFrontZ.data());
    r.frontSpeed = frontSpeed(c.T, c.Z);
    r.depthAtFront = depthAtMeasuredFront(c);
    r.medianDepthAtFront = median(r.depthAtFront);
    const double n = std::sqrt(mm::kHeightRatio);
    r.heightRms = rmsDifference(delayed(c.tau, c.H, mm::kHeightTau.data(), heightRows(), 0.0),
                                mm::kHeightH.data());
    r.heightRmsDelayed = rmsDifference(
        delayed(c.tau, c.H, mm::kHeightTau.data(), heightRows(), r.delay / n), mm::kHeightH.data());
    return r;
}

CaseResult run(const Options& options) {
    CaseResult result;
    result.name = "martin_moyce";
    result.title = "Collapse of a water column (Martin & Moyce 1952, n^2 = 2, a = 2.25 in)";
    const std::vector<int> resolutions =
        options.quick ? std::vector<int>{20, 30, 40} : std::vector<int>{20, 40, 80};
    std::vector<Collapse> runs;
    std::vector<Comparison> comparisons;
    for (int across : resolutions) {
        runs.push_back(collapse(across, 0.0, 0.0f, options));
        comparisons.push_back(compare(runs.back()));
    }
    // The gate, at the middle resolution: reported, not checked.
    const Collapse gated = collapse(resolutions[1], kGateSpeed, 0.0f, options);
    const Comparison gatedComparison = compare(gated);
    // Water's surface tension, instant release, at the middle resolution:
    // reported, in the full run only (its capillary substeps would add about
    // a quarter to the quick run that the test suite runs).
    std::optional<Collapse> capillary;
    std::optional<Comparison> capillaryComparison;
    if (!options.quick) {
        capillary = collapse(resolutions[1], 0.0, kWaterSurfaceTension, options);
        capillaryComparison = compare(*capillary);
    }
    const std::vector<double> tableT(mm::kFrontT.begin(), mm::kFrontT.end());
    const std::vector<double> tableZ(mm::kFrontZ.begin(), mm::kFrontZ.end());
    const std::vector<double> tableTau(mm::kHeightTau.begin(), mm::kHeightTau.end());
    const std::vector<double> tableH(mm::kHeightH.begin(), mm::kHeightH.end());
    plot::Panel front{"Surge front (simulation delayed by the fitted gate delay)",
                      "T = n t sqrt(g/a)",
                      "Z = x / a",
                      {}};
    plot::Panel height{"Residual column at the back wall (as simulated)",
                       "tau = t sqrt(g/a)",
                       "H = eta / (n^2 a)",
                       {}};
    plot::Panel convergence{"Convergence: distance from the experiment (log-log)",
                            "particles across a",
                            "RMS difference",
                            {}};
    convergence.logX = convergence.logY = true;
    plot::Panel raw{
        "Surge front as simulated (no delay): instant release, a gate (full run: surface tension)",
        "T = n t sqrt(g/a)",
        "Z = x / a",
        {}};
    plot::Panel tongue{"Simulated depth where the experiment saw its front (no delay)",
                       "T = n t sqrt(g/a)",
                       "depth at x = Z_exp a (mm)",
                       {}};
    front.series.push_back(detail::record(result, "Martin & Moyce Table 2", "T", tableT, "Z",
                                          tableZ, plot::Style::Points));
    height.series.push_back(detail::record(result, "Martin & Moyce Table 6", "tau", tableTau, "H",
                                           tableH, plot::Style::Points));
    raw.series.push_back({"Martin & Moyce Table 2", tableT, tableZ, plot::Style::Points});
    raw.series.push_back(detail::record(
        result, fmt::format("{} across a, gate lifted at {:.2f} m/s", gated.across, kGateSpeed),
        "T", gated.T, "Z", gated.Z, plot::Style::Dashed));
    if (capillary)
        raw.series.push_back(detail::record(result,
                                            fmt::format("{} across a, surface tension {} N/m",
                                                        capillary->across, kWaterSurfaceTension),
                                            "T", capillary->T, "Z", capillary->Z,
                                            plot::Style::Dashed));
    std::vector<double> across, frontRms, heightRms;
    for (std::size_t k = 0; k < runs.size(); ++k) {
        const Collapse& c = runs[k];
        const Comparison& cmp = comparisons[k];
        const std::string label = fmt::format("{} across a, dT = {:.2f}", c.across, cmp.delay);
        // The front up to T = 4 (the table ends at 3.33); all of it is in the third panel.
        std::vector<double> T, Z;
        for (std::size_t i = 0; i < c.T.size() && c.T[i] + cmp.delay <= 4.0; ++i) {
            T.push_back(c.T[i] + cmp.delay);
            Z.push_back(c.Z[i]);
        }
        front.series.push_back(detail::record(result, label + " front", "T_delayed", T, "Z", Z));
        height.series.push_back(detail::record(result, fmt::format("{} across a height", c.across),
                                               "tau", c.tau, "H", c.H));
        raw.series.push_back({fmt::format("{} across a", c.across), c.T, c.Z, plot::Style::Line});
        std::vector<double> depthMm;
        for (double d : cmp.depthAtFront) depthMm.push_back(1000.0 * d);
        tongue.series.push_back(detail::record(
            result, fmt::format("{} across a depth at the experiment's front", c.across), "T",
            tableT, "depth_mm", depthMm, plot::Style::Line));
        across.push_back(c.across);
        frontRms.push_back(cmp.frontRms);
        heightRms.push_back(cmp.heightRms);
    }
    convergence.series.push_back(detail::record(result, "front Z RMS", "particles_across", across,
                                                "rms", frontRms, plot::Style::Line));
    convergence.series.push_back(detail::record(result, "height H RMS", "particles_across", across,
                                                "rms", heightRms, plot::Style::Line));
    result.figure = {result.title, {front, height, raw, tongue, convergence}, 2};

    const Comparison& fine = comparisons.back();
    const Comparison& mid = comparisons[comparisons.size() - 2];
    const std::string table2 = "Martin & Moyce 1952, Table 2";
    const std::string table6 = "Martin & Moyce 1952, Table 6";
    const double mark = 2.0 / 9.0;  // the front marks: 0.5 in on a = 2.25 in
    result.checks.push_back(
        {fmt::format("surge front Z, RMS difference ({} across a)", runs.back().across),
         fine.frontRms, 0.0, mark / 2, "", table2,
         "half the spacing of the experiment's marks on the plate (0.5 in = 2/9 of a): the "
         "readings resolve no finer"});
    result.checks.push_back(
        {"fitted gate delay dT", fine.delay, kMaxDelay / 2, kMaxDelay / 2, "",
         "an instant release against the experiment's gate",
         "the experiment's clock can only start early, never late (dT >= 0); a delay beyond 0.5 "
         "(27 ms) would hide a front that runs too fast"});
    const double tableSpeed = frontSpeed(tableT, tableZ);
    result.checks.push_back(
        {"surge speed dZ/dT for T >= 2.2", fine.frontSpeed, tableSpeed, 0.1 * tableSpeed, "",
         table2 + " (line fitted to T >= 2.2)",
         "10 %: the experiment's floor is no-slip and its thin tip feels friction and surface "
         "tension; the simulated floor is free-slip. Independent of the gate delay"});
    result.checks.push_back(
        {fmt::format("residual height H, RMS difference (tau <= {})", kLastTau), fine.heightRms,
         0.0, 1.0 / 18.0, "", table6,
         "one step of the experiment's height marks (0.25 in = 1/18 of the column height)"});
    std::vector<double> change;
    for (std::size_t k = 0; k < fine.frontAtTable.size(); ++k)
        change.push_back(std::fabs(fine.frontAtTable[k] - mid.frontAtTable[k]));
    result.checks.push_back(
        {fmt::format("front change {} -> {} across a (largest over Table 2)",
                     runs[runs.size() - 2].across, runs.back().across),
         *std::max_element(change.begin(), change.end()), 0.0, mark / 2, "", "self-convergence",
         "doubling the resolution moves the front by less than the experiment resolves"});
    // Convergence: the distances from the experiment at the three resolutions.
    Convergence delayedStudy{
        "surge front Z, RMS after the fitted delay", "a / particles across", {}, {}};
    Convergence rawStudy{
        "surge front Z, RMS as simulated (no delay)", "a / particles across", {}, {}};
    Convergence heightStudy{"residual height H, RMS", "a / particles across", {}, {}};
    for (std::size_t k = 0; k < runs.size(); ++k) {
        for (Convergence* study : {&delayedStudy, &rawStudy, &heightStudy})
            study->h.push_back(1.0 / runs[k].across);
        delayedStudy.error.push_back(comparisons[k].frontRms);
        rawStudy.error.push_back(comparisons[k].frontRmsRaw);
        heightStudy.error.push_back(comparisons[k].heightRms);
    }
    // The surge front's distance from the experiment (after the fitted
    // delay) is reported, not checked to fall: it is 0.041 at 20, 30 and 40
    // across a (within 1 %) since the substeps respect solver.depth_limit
    // (the coarse column no longer slams as it starts: 0.048 at 20 across
    // before), the experiment's own scatter; that the front no longer
    // changes with the resolution is the "front change" check.
    result.checks.push_back(
        convergenceCheck(heightStudy, "the draining column is resolved better by finer particles"));
    result.convergence = {delayedStudy, heightStudy, rawStudy};
    std::string perResolution;
    const auto row = [&](const Collapse& c, const Comparison& k, const std::string& release) {
        return fmt::format(
            "| {} | {} | {} | {:.3f} | {:.1f} | {:.2f} | {:.3f} | {:.3f} | {:.3f} | {:.3f} |\n",
            c.across, c.particles, release, k.frontRmsRaw, 1000.0 * k.medianDepthAtFront, k.delay,
            k.frontRms, k.frontSpeed, k.heightRms, k.heightRmsDelayed);
    };
    for (std::size_t k = 0; k < runs.size(); ++k)
        perResolution += row(runs[k], comparisons[k], "instant");
    perResolution += row(gated, gatedComparison, fmt::format("gate at {:.2f} m/s", kGateSpeed));
    if (capillary)
        perResolution += row(*capillary, *capillaryComparison,
                             fmt::format("instant, surface tension {} N/m", kWaterSurfaceTension));
    result.notes = fmt::format(
        "A column a = 0.05715 m wide and 2a high in a tank 14a long, 4 particle layers deep "
        "between free-slip walls (a two-dimensional flow, as the experiment's channel), "
        "released at t = 0; frames every 4 ms; default solver settings (4 iterations, "
        "adaptive substeps, XSPH c = 0.01). Front: the farthest particle with at least half "
        "the rest density, plus its radius; height: the highest such particle within one "
        "spacing of the back wall, plus its radius. One constant delay dT is fitted to the "
        "front (in steps of 0.01 over [0, 0.5]). The height is compared as simulated; with "
        "the front's delay applied to it as well (dT / n in tau) it agrees less well (last "
        "column). The gate row: the column held by a gate (a plate a/10 thick) lifted from t = "
        "0 at {:.2f} m/s, the slowest opening Lauber & Hager's criterion (opening time <= "
        "sqrt(2 h0 / g)) counts as instantaneous, frames of 0.5 ms: its raw front is no closer "
        "to the experiment than the instant release's (the water squeezed under the rising "
        "gate leaves as a jet along the floor), so the gate does not explain the experiment's "
        "late start. Depth at the experiment's front: at each row of Table 2, the simulated "
        "water's depth (top of the highest particle with half the rest density in a strip one "
        "spacing wide) at x = Z a, without delay; its median over the rows. It is about the "
        "same at every resolution: the simulated surge runs ahead of the experiment's by a "
        "tongue of water thinner than that, which the experiment's front did not have. The "
        "last row (full run only): the instant release with water's surface tension ({} N/m, "
        "fluid.surface_tension). The experiment's surge speed is {:.3f} per unit T.\n\n"
        "| particles across a | particles | release | front RMS, no delay | simulated depth at "
        "the experiment's front, median (mm) | fitted dT | front RMS after dT | dZ/dT | height "
        "RMS | height RMS with dT |\n| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- "
        "|\n{}",
        kGateSpeed, kWaterSurfaceTension, tableSpeed, perResolution);
    return result;
}

}  // namespace

Case martinMoyceCase() {
    return {"martin_moyce",
            "column collapse against Martin & Moyce 1952 Tables 2 and 6, three resolutions", run,
            /*resolutionStudy=*/true};
}

}  // namespace pbf::validation
