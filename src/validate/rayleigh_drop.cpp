// Rayleigh (1879): a free drop of radius R released as a slightly prolate
// ellipsoid oscillates in its mode 2 (l = 2) at
//   omega^2 = l (l - 1) (l + 2) sigma / (rho R^3) = 8 sigma / (rho R^3),
// a closed form for small amplitudes of an inviscid drop (Lamb,
// "Hydrodynamics", sec. 275); viscosity damps it (Lamb sec. 355) and lowers
// the frequency by a second-order amount. The case measures the frequency
// of the drop's quadrupole moment at three resolutions: a check that
// sigma in N/m gives water's capillary dynamics (docs/surface_tension.md).
// The fit gives the damped frequency omega_d and the decay rate beta of
// A e^{-beta t} cos(omega_d t); Rayleigh's is the undamped one,
// omega_0 = sqrt(omega_d^2 + beta^2) (Lamb sec. 355: a damped linear
// oscillator), which the checks compare.
// The cohesion's strength is calibrated with this case at the finest
// resolution (SolverConstants, kCohesionCalibration); the coarser ones are
// predictions.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "validate/drops.hpp"
#include "validate/measure.hpp"

namespace pbf::validation {
namespace {

constexpr double kSigma = 0.0728;  // N/m, water at 20 C
constexpr double kRho = 1000.0;
constexpr double kRadius = 0.005;    // m: a 1 cm drop
constexpr double kAmplitude = 0.15;  // semi-axes R (1 + e) along y, R / sqrt(1 + e) across

// A damped cosine A e^{-beta t} cos(omega t + phi) + C fitted to (t, q) by
// least squares: for each (omega, beta) on a grid the linear parameters are
// solved exactly (variable projection); the grid is refined around the best.
struct DampedFit {
    double omega = 0.0;
    double beta = 0.0;
    double residual = std::numeric_limits<double>::infinity();  // RMS
};

DampedFit fitDampedCosine(const std::vector<double>& t, const std::vector<double>& q,
                          double omegaGuess) {
    auto residualOf = [&](double omega, double beta) {
        // Normal equations of q ~ c1 e cos + c2 e sin + c0.
        double m[3][3] = {}, v[3] = {};
        for (std::size_t k = 0; k < t.size(); ++k) {
            const double e = std::exp(-beta * t[k]);
            const double f[3] = {e * std::cos(omega * t[k]), e * std::sin(omega * t[k]), 1.0};
            for (int a = 0; a < 3; ++a) {
                v[a] += f[a] * q[k];
                for (int b = 0; b < 3; ++b) m[a][b] += f[a] * f[b];
            }
        }
        double c[3];
        for (int a = 0; a < 3; ++a)
            for (int b = a + 1; b < 3; ++b) {
                const double f = m[b][a] / m[a][a];
                for (int k = a; k < 3; ++k) m[b][k] -= f * m[a][k];
                v[b] -= f * v[a];
            }
        for (int a = 2; a >= 0; --a) {
            c[a] = v[a];
            for (int b = a + 1; b < 3; ++b) c[a] -= m[a][b] * c[b];
            c[a] /= m[a][a];
        }
        double sum = 0.0;
        for (std::size_t k = 0; k < t.size(); ++k) {
            const double e = std::exp(-beta * t[k]);
            const double r = q[k] - (c[0] * e * std::cos(omega * t[k]) +
                                     c[1] * e * std::sin(omega * t[k]) + c[2]);
            sum += r * r;
        }
        return std::sqrt(sum / double(t.size()));
    };
    DampedFit best;
    double omegaLo = 0.5 * omegaGuess, omegaHi = 1.5 * omegaGuess;
    double betaLo = 0.0, betaHi = 0.5 * omegaGuess;
    for (int round = 0; round < 4; ++round) {
        const int steps = 60;
        for (int i = 0; i <= steps; ++i)
            for (int j = 0; j <= steps; ++j) {
                const double omega = omegaLo + (omegaHi - omegaLo) * i / steps;
                const double beta = betaLo + (betaHi - betaLo) * j / steps;
                const double r = residualOf(omega, beta);
                if (r < best.residual) best = {omega, beta, r};
            }
        const double dOmega = 2.0 * (omegaHi - omegaLo) / steps;
        const double dBeta = 2.0 * (betaHi - betaLo) / steps;
        omegaLo = best.omega - dOmega, omegaHi = best.omega + dOmega;
        betaLo = std::max(0.0, best.beta - dBeta), betaHi = best.beta + dBeta;
    }
    return best;
}

struct Run {
    double particlesAcross = 0.0;  // 2 R / spacing
    std::size_t particles = 0;
    double radius = 0.0;  // equivalent radius of the particles' volume
    double omegaTheory = 0.0;
    DampedFit fit;
    std::vector<double> t, q;
    double omega() const { return std::sqrt(fit.omega * fit.omega + fit.beta * fit.beta); }
    double error() const { return omega() / omegaTheory - 1.0; }
};

Run runDrop(double particlesAcross, const Options& options) {
    const float spacing = float(2.0 * kRadius / particlesAcross);
    WorldDef def = detail::waterWorld(0.5f * spacing, float(6.0 * kRadius), float(kSigma));
    def.name = "rayleigh_drop";
    // No XSPH: it smooths velocities by a fixed share per substep, and the
    // capillary substeps are short (the damping would depend on them).
    def.simulation.fluid.viscosity = 0.0f;
    const double omegaGuess = std::sqrt(8.0 * kSigma / (kRho * std::pow(kRadius, 3)));
    const double period = 2.0 * std::numbers::pi / omegaGuess;
    def.fps = float(40.0 / period);  // 40 samples per period
    // The ellipsoid's lattice sites, volume preserved.
    const double along = kRadius * (1.0 + kAmplitude),
                 across = kRadius / std::sqrt(1.0 + kAmplitude);
    const float reach = float(along + spacing);
    const float half = 0.5f * spacing;
    const std::vector<Vec3> sites =
        detail::latticeSites(def, {{-reach, -reach, -reach}, {reach, reach, reach}},
                             {half, half, half}, [&](const Vec3& x) {
                                 const double u = x.x / across, v = x.y / along, w = x.z / across;
                                 return u * u + v * v + w * w <= 1.0;
                             });
    World world = detail::worldOf(def, sites);
    Run run;
    run.particlesAcross = particlesAcross;
    run.particles = world.particleCount();
    run.radius = std::cbrt(3.0 * double(run.particles) / (4.0 * std::numbers::pi)) * spacing;
    run.omegaTheory = std::sqrt(8.0 * kSigma / (kRho * std::pow(run.radius, 3)));
    // The quadrupole moment <y^2 - (x^2 + z^2) / 2> / R^2: (b^2 - a^2) / (5 R^2)
    // for an ellipsoid of semi-axes b along y and a across.
    auto quadrupole = [&] {
        const std::vector<Vec3> x = detail::positions(world);
        const Vec3 c = detail::centroid(x);
        double sum = 0.0;
        for (const Vec3& p : x) {
            const Vec3 d = p - c;
            sum += double(d.y) * d.y - 0.5 * (double(d.x) * d.x + double(d.z) * d.z);
        }
        return sum / double(x.size()) / (kRadius * kRadius);
    };
    // 2.5 periods: the oscillation is well damped by then (PBF's projection
    // dissipates; particle noise of the released surface shows after).
    const double duration = 2.5 * period;
    run.t.push_back(0.0);
    run.q.push_back(quadrupole());
    while (world.time() < duration - 1e-9) {
        detail::step(world);
        run.t.push_back(world.time());
        run.q.push_back(quadrupole());
    }
    run.fit = fitDampedCosine(run.t, run.q, run.omegaTheory);
    if (options.progress)
        options.progress(fmt::format(
            "rayleigh_drop: {:.0f} particles across ({} particles): omega_0 {:.2f} rad/s, theory "
            "{:.2f} ({:+.1f} %); fitted omega_d {:.2f} rad/s, damping {:.1f} 1/s",
            run.particlesAcross, run.particles, run.omega(), run.omegaTheory, 100.0 * run.error(),
            run.fit.omega, run.fit.beta));
    return run;
}

CaseResult run(const Options& options) {
    CaseResult result;
    result.name = "rayleigh_drop";
    result.title = "Rayleigh drop: mode-2 oscillation frequency of a free drop";
    // Cheap enough (seconds) to run in full in the quick suite too.
    const std::vector<double> resolutions{8.0, 11.0, 16.0};
    std::vector<Run> runs;
    for (const double across : resolutions) runs.push_back(runDrop(across, options));

    plot::Panel signal{"Quadrupole moment of the drop", "t (s)", "<y^2 - (x^2 + z^2)/2> / R^2", {}};
    std::vector<double> across, error;
    for (const Run& r : runs) {
        signal.series.push_back(
            detail::record(result, fmt::format("{:.0f} particles across", r.particlesAcross), "t_s",
                           r.t, "quadrupole", r.q));
        across.push_back(r.particlesAcross);
        error.push_back(100.0 * std::fabs(r.error()));
    }
    plot::Panel convergence{
        "Frequency error", "particles across the drop", "|omega_0 / omega_Rayleigh - 1| (%)", {}};
    convergence.series.push_back(detail::record(result, "frequency error", "particles_across",
                                                across, "percent", error, plot::Style::Points));
    result.figure = {result.title, {signal, convergence}, 2};

    const Run& finest = runs.back();
    result.checks.push_back(
        {fmt::format("omega_0 at {:.0f} particles across", finest.particlesAcross), finest.omega(),
         finest.omegaTheory, 0.1 * finest.omegaTheory, "rad/s",
         "Rayleigh 1879: omega^2 = 8 sigma / (rho R^3)",
         "10 % at the finest resolution (issue 27; the cohesion's strength is calibrated there, "
         "the coarser resolutions are predictions)"});
    const double coarse = std::fabs(runs.front().error()), fine = std::fabs(finest.error());
    result.checks.push_back({"|error| at 16 minus |error| at 8 particles across", fine - coarse,
                             0.0, 0.0, "", "the error shrinks with resolution",
                             "issue 27: over three resolutions", Check::Bound::AtMost});
    std::string perRun;
    for (const Run& r : runs)
        perRun += fmt::format(
            "{:.0f} across ({} particles): omega_0 {:.1f} rad/s, theory {:.1f} "
            "({:+.1f} %), omega_d {:.1f} rad/s, damping {:.1f} 1/s; ",
            r.particlesAcross, r.particles, r.omega(), r.omegaTheory, 100.0 * r.error(),
            r.fit.omega, r.fit.beta);
    result.notes = fmt::format(
        "A {:.0f} mm drop of water (sigma {} N/m) without gravity, released at rest as a prolate "
        "ellipsoid (amplitude {}), XSPH off; omega_0 = sqrt(omega_d^2 + beta^2) from a damped "
        "cosine fitted to the quadrupole moment over 2.5 periods. {}",
        2e3 * kRadius, kSigma, kAmplitude, perRun);
    return result;
}

}  // namespace

Case rayleighDropCase() {
    return {"rayleigh_drop", "mode-2 oscillation of a free drop: Rayleigh's frequency", run};
}

}  // namespace pbf::validation
