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
// experiment's was held by a gate that took time to clear, so its front
// starts late. The front comparison therefore fits one constant delay (the
// gate delay, dT in [0, 0.5]); the fitted delay is reported and checked.
// The height is compared as simulated: applying the same delay to it makes
// the agreement worse (the simulated column drains later than the
// experiment's, which no start delay corrects); both numbers are reported.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

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

struct Collapse {
    int across = 0;  // particles across the column width a
    std::size_t particles = 0;
    std::vector<double> T, Z, tau, H;  // per frame
};

Collapse collapse(int across, const Options& options) {
    const double a = mm::kColumnWidth;
    const float r = float(a / (2.0 * across));
    const float depth = 4.0f * 2.0f * r;
    WorldDef def;
    def.name = "martin_moyce";
    def.simulation.domain = {{0, 0, 0}, {float(kTankLength * a), float(2.5 * a), depth}};
    def.simulation.particleRadius = r;
    def.fluidBlocks.push_back(
        {{{0, 0, 0}, {float(a), float(mm::kHeightRatio * a), depth}}, {0, 0, 0}});
    def.fps = 250.0f;  // frames of 4 ms: dT = 0.074 between samples
    World world(def);
    Collapse c;
    c.across = across;
    c.particles = world.particleCount();
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
        for (std::size_t i = 0; i < p.size(); ++i) {
            if (p.density[i] < halfRho0) continue;
            front = std::max(front, p.position.x[i]);
            if (p.position.x[i] < 2.0f * r) height = std::max(height, p.position.y[i]);
        }
        c.T.push_back(n * world.time() * rate);
        c.Z.push_back((front + r) / a);
        c.tau.push_back(world.time() * rate);
        c.H.push_back((height + r) / (mm::kHeightRatio * a));
    };
    measure();
    while (world.time() * rate < kLastTau + 0.05) {
        detail::step(world);
        measure();
    }
    if (options.progress)
        options.progress(fmt::format("martin_moyce: {} particles across a ({} particles) done",
                                     across, c.particles));
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

struct Comparison {
    double delay = 0.0;             // fitted gate delay, in T
    double frontRms = 0.0;          // Z, after the delay
    double frontSpeed = 0.0;        // dZ/dT fitted over T >= 2.2
    double heightRms = 0.0;         // H, as simulated
    double heightRmsDelayed = 0.0;  // H, after the front's delay (in tau: dT / n)
    std::vector<double> frontAtTable;
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
    r.frontSpeed = frontSpeed(c.T, c.Z);
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
        runs.push_back(collapse(across, options));
        comparisons.push_back(compare(runs.back()));
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
    plot::Panel convergence{
        "Convergence: distance from the experiment", "particles across a", "RMS difference", {}};
    plot::Panel raw{"Surge front as simulated (instant release, no delay)",
                    "T = n t sqrt(g/a)",
                    "Z = x / a",
                    {}};
    front.series.push_back(detail::record(result, "Martin & Moyce Table 2", "T", tableT, "Z",
                                          tableZ, plot::Style::Points));
    height.series.push_back(detail::record(result, "Martin & Moyce Table 6", "tau", tableTau, "H",
                                           tableH, plot::Style::Points));
    raw.series.push_back({"Martin & Moyce Table 2", tableT, tableZ, plot::Style::Points});
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
        across.push_back(c.across);
        frontRms.push_back(cmp.frontRms);
        heightRms.push_back(cmp.heightRms);
    }
    convergence.series.push_back(detail::record(result, "front Z RMS", "particles_across", across,
                                                "rms", frontRms, plot::Style::Line));
    convergence.series.push_back(detail::record(result, "height H RMS", "particles_across", across,
                                                "rms", heightRms, plot::Style::Line));
    result.figure = {result.title, {front, height, raw, convergence}, 2};

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
    std::string perResolution;
    for (std::size_t k = 0; k < runs.size(); ++k)
        perResolution += fmt::format("| {} | {} | {:.2f} | {:.3f} | {:.3f} | {:.3f} | {:.3f} |\n",
                                     runs[k].across, runs[k].particles, comparisons[k].delay,
                                     comparisons[k].frontRms, comparisons[k].frontSpeed,
                                     comparisons[k].heightRms, comparisons[k].heightRmsDelayed);
    result.notes = fmt::format(
        "A column a = 0.05715 m wide and 2a high in a tank 14a long, 4 particle layers deep "
        "between free-slip walls (a two-dimensional flow, as the experiment's channel), "
        "released at t = 0; frames every 4 ms; default solver settings (4 iterations, "
        "adaptive substeps, XSPH c = 0.01). Front: the farthest particle with at least half "
        "the rest density, plus its radius; height: the highest such particle within one "
        "spacing of the back wall, plus its radius. The experiment's gate is not simulated: "
        "one constant delay dT is fitted to the front (in steps of 0.01 over [0, 0.5]). The "
        "height is compared as simulated; with the front's delay applied to it as well (dT / n "
        "in tau) it agrees less well (last column): late in the collapse the simulated column "
        "stands higher than the experiment's, which no start delay corrects. The experiment's "
        "surge speed is {:.3f} per unit T.\n\n"
        "| particles across a | particles | dT | front RMS | dZ/dT | height RMS | height RMS "
        "with dT |\n| --- | --- | --- | --- | --- | --- | --- |\n{}",
        tableSpeed, perResolution);
    return result;
}

}  // namespace

Case martinMoyceCase() {
    return {"martin_moyce",
            "column collapse against Martin & Moyce 1952 Tables 2 and 6, three resolutions", run};
}

}  // namespace pbf::validation
