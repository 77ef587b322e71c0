// Pinch-off: a thread of water in zero gravity, its cross-section seeded
// with a perturbation at Rayleigh's fastest wavenumber, breaks into one drop
// per wavelength, and the drops stay apart (docs/surface_tension.md,
// "Strands let go"). The thread spans the domain between two walls that
// meet it at about 90 degrees (wall adhesion 0.5, no friction: near-symmetry
// planes; a free end would retract through the first bulge before any neck
// broke), three wavelengths long, bulges at the walls: three necks, two
// whole drops and a half at each wall.
//
// The linear theory (Rayleigh 1892; Eggers 1997 eq. 11): the seed grows at
// omega^2 = sigma / (rho R^3) kR (1 - k^2 R^2) I1(kR) / I0(kR); released at
// rest it grows as eps cosh(omega t) and reaches the radius at
// acosh(1 / eps) / omega. A neck has broken when the largest piece
// (particles linked closer than h) holds under 0.9 of the water: the first
// break is checked against the prediction (the necks are equivalent in the
// theory; next to a wall one broke up to 0.05 s later than in the middle,
// at a time that moves with the rounding), and every neck must have broken
// by 2.5 times the prediction (one drop per wavelength, a whole drop
// holding a third of the water).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "validate/drops.hpp"
#include "validate/measure.hpp"

namespace pbf::validation {
namespace {

constexpr double kSigma = 0.0728;      // N/m
constexpr double kRho = 1000.0;        // kg/m^3
constexpr double kSpacing = 0.0005;    // m: particles of 0.25 mm
constexpr double kWavenumber = 0.697;  // kR, the fastest-growing
constexpr double kSeed = 0.25;         // of the radius
constexpr int kWaves = 3;
constexpr double kFirstBreak = 0.9;  // the largest piece's share once a neck broke
constexpr double kAllBroken = 0.4;   // ... once every neck broke
constexpr double kDropShare = 0.05;  // a piece with this share of the water or more is a drop
constexpr double kDuration = 2.5;    // the run, in linear predictions

struct Thread {
    int across = 0;
    std::size_t particles = 0;
    double linearTime = 0.0;     // s
    double breakTime = 0.0;      // s, the first neck; NaN if none broke
    double allBrokenTime = 0.0;  // s, the last; NaN if one held
    int drops = 0;               // pieces of kDropShare or more, at the end
    int satellites = 0;          // the other pieces of more than one particle, at the end
    double largestAtEnd = 0.0;
    std::vector<double> t, share;
};

// The growth rate omega (1/s) of the linear theory at kR for radius R.
double growthRate(double R) {
    const double kR = kWavenumber;
    const double shape =
        kR * (1.0 - kR * kR) * std::cyl_bessel_i(1.0, kR) / std::cyl_bessel_i(0.0, kR);
    return std::sqrt(kSigma / (kRho * R * R * R) * shape);
}

Thread runThread(int across, const Options& options) {
    Thread out;
    out.across = across;
    const double R = 0.5 * across * kSpacing;
    const double wavelength = 2.0 * std::numbers::pi * R / kWavenumber;
    const double length = kWaves * wavelength;
    out.linearTime = std::acosh(1.0 / kSeed) / growthRate(R);
    WorldDef def = detail::waterWorld(float(0.5 * kSpacing), 1.0f, float(kSigma));
    def.name = fmt::format("pinch_off_{}", across);
    const float side = float(3.0 * R);
    def.simulation.domain = {{0.0f, -side, -side}, {float(length), side, side}};
    def.simulation.solver.wallAdhesion = 0.5f;
    def.simulation.solver.friction = 0.0f;
    def.fps = float(40.0 / out.linearTime);  // 40 samples to the linear prediction
    // The volume of the unseeded thread: the mean of r^2 is R^2 (1 + eps^2 / 2).
    const double scale = R / std::sqrt(1.0 + 0.5 * kSeed * kSeed);
    const std::vector<Vec3> sites = detail::latticeSites(
        def, def.simulation.domain, {float(0.5 * kSpacing), 0.0f, 0.0f}, [&](const Vec3& p) {
            const double r =
                scale * (1.0 + kSeed * std::cos(2.0 * std::numbers::pi * p.x / wavelength));
            return double(p.y) * p.y + double(p.z) * p.z < r * r;
        });
    World world = detail::worldOf(def, sites);
    out.particles = world.particleCount();
    const float link = world.constants().h;
    out.breakTime = out.allBrokenTime = std::nan("");
    std::vector<std::size_t> sizes;
    while (world.time() < kDuration * out.linearTime - 1e-9) {
        detail::step(world);
        sizes = detail::clusterSizes(detail::positions(world), link);
        const double share = double(sizes.front()) / double(out.particles);
        out.t.push_back(world.time());
        out.share.push_back(share);
        if (std::isnan(out.breakTime) && share < kFirstBreak) out.breakTime = world.time();
        if (std::isnan(out.allBrokenTime) && share < kAllBroken) out.allBrokenTime = world.time();
    }
    out.largestAtEnd = out.share.back();
    for (const std::size_t n : sizes) {
        if (double(n) >= kDropShare * double(out.particles))
            ++out.drops;
        else if (n > 1)
            ++out.satellites;
    }
    if (options.progress)
        options.progress(fmt::format(
            "pinch_off: {} across, {} particles: the first neck broke at {:.4f} s (linear "
            "prediction {:.4f} s), the last at {:.4f} s; {} drops and {} satellites at {:.3f} s, "
            "the largest {:.2f} of the water",
            across, out.particles, out.breakTime, out.linearTime, out.allBrokenTime, out.drops,
            out.satellites, out.t.back(), out.largestAtEnd));
    return out;
}

CaseResult run(const Options& options) {
    CaseResult result;
    result.name = "pinch_off";
    result.title = "Zero gravity: a seeded thread of water breaks into drops";
    const std::vector<int> resolutions =
        options.quick ? std::vector<int>{8} : std::vector<int>{8, 16};
    std::vector<Thread> threads;
    for (const int across : resolutions) threads.push_back(runThread(across, options));

    plot::Panel panel{"The largest piece", "t / linear prediction", "share of the water", {}};
    for (const Thread& th : threads) {
        std::vector<double> scaled;
        for (const double t : th.t) scaled.push_back(t / th.linearTime);
        panel.series.push_back(detail::record(result, fmt::format("{} across", th.across),
                                              "t_over_linear", scaled, "share", th.share));
    }
    panel.series.push_back(detail::record(result, "a neck broke", "t_over_linear",
                                          {0.0, kDuration}, "share", {kFirstBreak, kFirstBreak},
                                          plot::Style::Dashed));
    panel.series.push_back(detail::record(result, "every neck broke", "t_over_linear",
                                          {0.0, kDuration}, "share", {kAllBroken, kAllBroken},
                                          plot::Style::Dashed));
    result.figure = {result.title, {panel}, 1};

    std::string notes = fmt::format(
        "Threads of water (sigma {} N/m) without gravity, {} wavelengths at kR = {} seeded with "
        "{:.0f} % of the radius, between walls of adhesion 0.5 without friction, particles of "
        "{} mm. ",
        kSigma, kWaves, kWavenumber, 100.0 * kSeed, 1e3 * kSpacing);
    for (const Thread& th : threads) {
        const std::string label = fmt::format("{} across", th.across);
        result.checks.push_back(
            {fmt::format("first break / the linear prediction, {}", label),
             th.breakTime / th.linearTime, 1.0, 0.2, "",
             "acosh(1 / eps) / omega, omega^2 = sigma / (rho R^3) kR (1 - k^2 R^2) I1 / I0 "
             "(Rayleigh 1892)",
             "20 %: the last stage of a neck is not linear"});
        result.checks.push_back(
            {fmt::format("drops at 2.5 times the linear prediction, {}", label), double(th.drops),
             double(kWaves + 1), 0.0, "",
             "one per wavelength: two whole drops and a half at each wall",
             "each of over 5 % of the water; satellites not counted; a merge or a neck that "
             "holds fails it"});
        notes += fmt::format(
            "{}: {} particles, the first neck broke at {:.4f} s against {:.4f} s, the last at "
            "{:.4f} s; at {:.3f} s {} drops, {} satellites, the largest piece {:.3f} of the "
            "water. ",
            label, th.particles, th.breakTime, th.linearTime, th.allBrokenTime, th.t.back(),
            th.drops, th.satellites, th.largestAtEnd);
    }
    result.notes = notes;
    return result;
}

}  // namespace

Case pinchOffCase() {
    return {"pinch_off", "zero gravity: a seeded thread breaks into one drop per wavelength", run};
}

}  // namespace pbf::validation
