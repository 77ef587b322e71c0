// Laplace (1806), Young (1805): the pressure inside a resting drop exceeds
// the outside's by 2 sigma / R. PBF has no pressure variable, but its
// density constraint exerts one: the position corrections of a substep,
// divided by dt^2, are the constraint's force per mass, and pair by pair
// they are equal and opposite (lambda_i + lambda_j, antisymmetric kernel
// gradient). The solver records each particle's correction per dt^2 of
// the substep (the solve acceleration) only while the warm start is on, so
// the case runs the smallest warm start, 1e-6: it moves the particles by a
// millionth of the last correction, which leaves the solver's default
// dynamics. (A warm start of 0.8 would not: it acts on compressed particles
// only, is not pairwise, spins the drops (a third of the 3 mm drop's
// kinetic energy) and raised the 6 mm drop's pressure from 17.4 to
// 20.9 Pa.) Averaged over many
// frames of two resting drops, the smaller one cut from the lattice at
// four shifts (sampledDrop).
//
// The pressure in Laplace's sense is the bulk's total normal stress
// (Irving & Kirkwood 1950): every force across a plane inside the drop per
// area, plus the momentum the particles carry across it. The bulk carries
// cohesion too (particles the jitter drops below the surface density pull),
// so the constraint's force alone is not the pressure. The case splits the
// constraint's force pair by pair (detail::fitConstraintPairs) and reads
// constraint + cohesion pull + core + momentum flux across the inner disc
// of the equator, r < R / 2: that must be 2 sigma / R and scale as 1 / R.
// (The curvature force acts on the surface band alone: none of it crosses
// the inner disc. The constraint's force across the whole equator would
// not do: the bulk's cohesion partly takes it back.)
//
// Two checks of the measure: Newton's third law on the upper half at rest
// (across the whole equator the constraint's force, the cohesion's core and
// the momentum flux must equal the cohesion's pull across it and the
// curvature force on the upper half's particles, each summed here from the
// particles, EquatorForces), and the pair fit reproducing the constraint's
// force across the whole equator.
//
// Why the half-step rerun (docs/surface_tension.md, "Why this model"): with
// the cohesion alone the pressure followed the particles' jitter (with the
// substep halved the drop was quieter and the pressure fell tenfold); a
// pressure set by sigma does not follow the substep.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

#include "backend/reference/equations.hpp"
#include "backend/reference/neighbor_grid.hpp"
#include "backend/reference/particle_sums.hpp"
#include "validate/concurrent.hpp"
#include "validate/constraint_pairs.hpp"
#include "validate/drops.hpp"
#include "validate/measure.hpp"

namespace pbf::validation {
namespace {

constexpr double kSigma = 0.0728;
// s: a resting drop settles for kSettle (a few capillary times of these
// drops), then its forces are averaged for kAverage (the checked drops) or
// kStudyAverage (the 1 / R study's, for its cost; restingDrop says why the
// checked ones need longer).
constexpr double kSettle = 0.15, kAverage = 0.45, kStudyAverage = 0.15;

// The forces the lower half of the drop exerts on the upper half across the
// plane y = c, N, upward positive: the pair forces of the pairs the plane
// separates and the momentum the particles carry across it (Irving &
// Kirkwood 1950), and the cohesion's state.
struct EquatorForces {
    double pull = 0.0;           // the cohesion's pull (pairs with a surface particle)
    double core = 0.0;           // the cohesion's repulsive core
    double kinetic = 0.0;        // sum m v_y^2 / slab over a slab two spacings thick
    double energy = 0.0;         // the cohesion energy E = eps sum_i s_i (rho~0 - rho~_i), J
    double surface = 0.0;        // particles on the surface (density below 0.98 rho0)
    double kineticEnergy = 0.0;  // J
    // The constraint's force from the pair fit: across the whole equator
    // (to compare with the per-particle sum) and across the inner disc
    // r < R / 2, with the pull, core and momentum flux across that disc; the
    // fit's relative residual; everything but the flux across r < 0.7 R (a
    // check that the bulk's stress is uniform).
    double constraintFit = 0.0, constraintInner = 0.0, pullInner = 0.0, coreInner = 0.0;
    double kineticInner = 0.0, totalWide = 0.0, fitResidual = 0.0;
    // The curvature force (equations.hpp) on the upper half's particles, N
    // upward (a one-body force on the surface band: it crosses no disc).
    double curvature = 0.0;
    // The band's A-weighted mean distance from the centre (m): how deep it
    // lies inside the volume's radius (the force's surfaceOffset).
    double bandRadius = 0.0;

    EquatorForces& operator+=(const EquatorForces& o) {
        pull += o.pull, core += o.core, kinetic += o.kinetic, energy += o.energy;
        surface += o.surface, kineticEnergy += o.kineticEnergy;
        constraintFit += o.constraintFit, constraintInner += o.constraintInner;
        pullInner += o.pullInner, coreInner += o.coreInner, kineticInner += o.kineticInner;
        totalWide += o.totalWide, fitResidual += o.fitResidual;
        curvature += o.curvature, bandRadius += o.bandRadius;
        return *this;
    }
    EquatorForces& operator/=(double n) {
        for (double* x : {&pull, &core, &kinetic, &energy, &surface, &kineticEnergy, &constraintFit,
                          &constraintInner, &pullInner, &coreInner, &kineticInner, &totalWide,
                          &fitResidual, &curvature, &bandRadius})
            *x /= n;
        return *this;
    }
    // N upward on the upper half across the inner disc: the bulk's pressure
    // times its area.
    double innerTotal() const {
        return constraintInner + pullInner + coreInner + kineticInner;
    }
};

// From the end-of-step state: the positions and the surface layer the
// cohesion used (reference::surfaceLayer, cohesionTerm: the equations of the
// solver's passes).
EquatorForces equatorForces(const World& world, double plane, double radius) {
    const SolverConstants& c = world.constants();
    const ParticleStore& p = world.particles();
    const std::vector<Vec3> x = detail::positions(world);
    const double m = c.particleMass, d = std::sqrt(double(c.cohesionMinDistance2));
    Aabb box{x.front(), x.front()};
    for (const Vec3& q : x) {
        box.min = {std::min(box.min.x, q.x), std::min(box.min.y, q.y), std::min(box.min.z, q.z)};
        box.max = {std::max(box.max.x, q.x), std::max(box.max.y, q.y), std::max(box.max.z, q.z)};
    }
    const Vec3 margin{c.h, c.h, c.h};
    reference::NeighborGrid grid({box.min - margin, box.max + margin}, c.h);
    grid.build(x);
    // epsilon from cohesionScale = 6 c6 epsilon; rho~ with the flat top W(max(r, d)).
    const double epsilon = double(c.cohesionScale) / (6.0 * double(c.poly6.coefficient));
    const auto flat = [&](double r2) { return double(c.poly6.value(float(std::max(r2, d * d)))); };
    double full = flat(0.0);  // rho~0 / m: the rest lattice's sum, self included
    const int reach = int(std::ceil(c.h / d));
    for (int a = -reach; a <= reach; ++a)
        for (int b = -reach; b <= reach; ++b)
            for (int k = -reach; k <= reach; ++k)
                if (a || b || k) full += flat((a * a + b * b + k * k) * d * d);
    std::vector<std::vector<std::uint32_t>> neighbours(x.size());
    std::vector<Vec3> solve(x.size());
    for (std::size_t i = 0; i < x.size(); ++i) {
        for (const std::uint32_t j : grid.neighbors(i))
            if (j != i && lengthSquared(x[i] - x[j]) < c.h * c.h) neighbours[i].push_back(j);
        solve[i] = p.solveAcceleration.get(i);
    }
    // The curvature force's acceleration, as the solver's passes compute it.
    const std::size_t n = x.size();
    std::vector<Vec3> gradient(n), normal(n);
    std::vector<float> kappa(n);
    for (std::size_t i = 0; i < n; ++i)
        gradient[i] = reference::colourGradient(c, x, neighbours[i], i);
    for (std::size_t i = 0; i < n; ++i)
        normal[i] = reference::bandNormal(c, x, gradient, neighbours[i], i);
    for (std::size_t i = 0; i < n; ++i)
        kappa[i] = reference::curvature(c, x, gradient, normal, neighbours[i], i);
    const detail::ConstraintPairs fit = detail::fitConstraintPairs(x, solve, neighbours, c.spiky);
    const Vec3 centre = detail::centroid(x);
    const double inner2 = 0.25 * radius * radius, wide2 = 0.49 * radius * radius;
    const auto fromAxis2 = [&](const Vec3& q) {
        const Vec3 off = q - centre;
        return double(off.x) * off.x + double(off.z) * off.z;
    };
    EquatorForces f;
    f.fitResidual = fit.residual;
    double bandWeight = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        const float w = reference::surfaceBandWeight(c, gradient[i]);
        f.bandRadius += double(w) * length(x[i] - centre);
        bandWeight += w;
    }
    f.bandRadius /= bandWeight;
    std::vector<float> layer(n);
    for (std::size_t i = 0; i < n; ++i)
        layer[i] = reference::surfaceLayer(c, nullptr, x, p.density[i], neighbours[i], i);
    for (std::size_t i = 0; i < x.size(); ++i) {
        const bool si = layer[i] > 0.0f;
        double sum = flat(0.0);
        for (const std::uint32_t j : grid.neighbors(i)) {
            const Vec3 rij = x[i] - x[j];
            const float r2 = lengthSquared(rij);
            sum += flat(r2);
            if (!(x[i].y > plane) || x[j].y > plane) continue;
            const bool sj = layer[j] > 0.0f;
            const double fy = m * double(reference::cohesionTerm(c, rij, si, sj).y);
            (r2 < c.cohesionCoreDistance2 ? f.core : f.pull) += fy;
            const double cy =
                r2 < c.h * c.h && j != i
                    ? m * (fit.L[i] + fit.L[j]) * double(c.spiky.gradient(rij, std::sqrt(r2)).y)
                    : 0.0;
            f.constraintFit += cy;
            // Which disc the pair crosses: where its midpoint is from the axis.
            const double axis2 = fromAxis2(0.5f * (x[i] + x[j]));
            if (axis2 < wide2) f.totalWide += cy + fy;
            if (axis2 < inner2) {
                f.constraintInner += cy;
                (r2 < c.cohesionCoreDistance2 ? f.coreInner : f.pullInner) += fy;
            }
        }
        if (x[i].y > plane)
            f.curvature += m * double(reference::curvatureForceVelocityChange(
                                          c, 1.0f, x, gradient, kappa, neighbours[i], i)
                                          .y);
        if (si) {
            f.energy += epsilon * m * (full - sum);
            f.surface += 1.0;
        }
        const Vec3 v = p.velocity.get(i);
        f.kineticEnergy += 0.5 * m * double(lengthSquared(v));
        if (std::fabs(x[i].y - plane) < d) {
            const double flux = m * double(v.y) * v.y / (2.0 * d);
            f.kinetic += flux;
            if (fromAxis2(x[i]) < inner2) f.kineticInner += flux;
        }
    }
    return f;
}

struct Drop {
    double radius = 0.0;           // from the particles' volume, m
    double constraintShare = 0.0;  // Pa: the constraint's force across the equator / pi R^2
    double pressure = 0.0;         // Pa: the bulk's total stress across r < R / 2
    double dt = 0.0;               // the substep (adaptive: its capillary limit), s
    double mass = 0.0;             // of a particle, kg
    std::size_t particles = 0;
    int samplings = 1;           // lattice shifts averaged (sampledDrop)
    double pressureError = 0.0;  // Pa: the standard error of the samplings' mean
    EquatorForces mean;          // averaged over the same frames
    std::vector<double> t, p;
    double area() const { return std::numbers::pi * radius * radius; }
    double innerArea() const { return 0.25 * area(); }
    double vrms() const { return std::sqrt(2.0 * mean.kineticEnergy / (mass * double(particles))); }
    // (constraint + core + kinetic) / (pull + curvature force) on the upper
    // half: 1 when the constraint measure is the force it claims to be.
    double balance() const {
        return (constraintShare * area() + mean.core + mean.kinetic) /
               -(mean.pull + mean.curvature);
    }
    // The pair fit's constraint force across the equator over the per-particle sum.
    double fitAgreement() const { return mean.constraintFit / (constraintShare * area()); }
};

// substepsPerFrame 0: the adaptive substep (the capillary limit decides).
// `average`: how long the forces are averaged after the drop has settled
// for 0.15 s (a few capillary times of these drops). A 3 mm drop's figure
// moves by 0.07 of 2 sigma / R from one 0.15 s window to the next
// (41.1 / 48.0 / 45.7 Pa over 0.15-0.30-0.45-0.60 s); the 6 mm drop's by
// 0.02: the checked drops average 0.45 s.
Drop restingDrop(double radius, float spacing, int substepsPerFrame, double average,
                 const Options& options, const Vec3& shift = {}) {
    WorldDef def = detail::waterWorld(0.5f * spacing, float(5.0 * radius), float(kSigma));
    def.name = "laplace";
    def.simulation.solver.warmStart = 1e-6f;  // records the solve acceleration (above)
    def.simulation.fluid.viscosity = 0.05f;   // the drop comes to rest
    def.fps = 200.0f;
    if (substepsPerFrame > 0) {
        def.simulation.solver.timeStepMode = TimeStepMode::Fixed;
        def.simulation.solver.fixedSubsteps = substepsPerFrame;
    }
    const float half = 0.5f * spacing;
    const float reach = float(radius) + spacing;
    const std::vector<Vec3> sites = detail::latticeSites(
        def, {{-reach, -reach, -reach}, {reach, reach, reach}},
        {half + shift.x * spacing, half + shift.y * spacing, half + shift.z * spacing},
        [&](const Vec3& x) { return length(x) <= float(radius); });
    World world = detail::worldOf(def, sites);
    Drop drop;
    drop.particles = world.particleCount();
    drop.radius = std::cbrt(3.0 * double(drop.particles) / (4.0 * std::numbers::pi)) * spacing;
    drop.dt = substepsPerFrame > 0 ? 1.0 / (double(def.fps) * substepsPerFrame)
                                   : double(world.constants().capillaryTimeStep);
    const double m = world.constants().particleMass;
    drop.mass = m;
    double sum = 0.0;
    int samples = 0;
    while (world.time() < kSettle + average - 1e-9) {
        detail::step(world);
        const ParticleStore& p = world.particles();
        const Vec3 c = detail::centroid(detail::positions(world));
        double force = 0.0;
        for (std::size_t i = 0; i < p.size(); ++i)
            if (p.position.y[i] > c.y) force += m * p.solveAcceleration.y[i];
        const double pressure = force / drop.area();
        drop.t.push_back(world.time());
        drop.p.push_back(pressure);
        if (world.time() > kSettle) {
            sum += pressure;
            ++samples;
            drop.mean += equatorForces(world, c.y, drop.radius);
        }
    }
    drop.constraintShare = sum / samples;
    drop.mean /= samples;
    drop.pressure = drop.mean.innerTotal() / drop.innerArea();
    if (options.progress)
        options.progress(fmt::format(
            "laplace: drop of {:.2f} mm ({} particles, substep {:.0f} us): pressure {:.1f} Pa "
            "(across r < R/2: constraint {:.1f}, pull {:.1f}, core {:.1f}, kinetic {:.1f}; across "
            "r < 0.7 R without the kinetic {:.1f}), 2 sigma / R = {:.1f} Pa; across the whole "
            "equator (Pa): constraint {:.1f} (pair fit {:.1f}, residual {:.2f}), cohesion pull "
            "{:.1f}, core {:.1f}, kinetic {:.1f} (balance {:.3f}); {:.0f} surface particles, "
            "cohesion energy / area {:.4f} N/m, rms speed {:.3f} m/s; curvature force on the "
            "upper half {:.1f} Pa, its band {:.2f} spacings inside R",
            1e3 * drop.radius, drop.particles, 1e6 * drop.dt, drop.pressure,
            drop.mean.constraintInner / drop.innerArea(), drop.mean.pullInner / drop.innerArea(),
            drop.mean.coreInner / drop.innerArea(), drop.mean.kineticInner / drop.innerArea(),
            drop.mean.totalWide / (0.49 * drop.area()), 2.0 * kSigma / drop.radius,
            drop.constraintShare, drop.mean.constraintFit / drop.area(), drop.mean.fitResidual,
            drop.mean.pull / drop.area(), drop.mean.core / drop.area(),
            drop.mean.kinetic / drop.area(), drop.balance(), drop.mean.surface,
            drop.mean.energy / (4.0 * drop.area()), drop.vrms(), drop.mean.curvature / drop.area(),
            (drop.radius - drop.mean.bandRadius) / double(spacing)));
    return drop;
}

// The mean of the drop cut from the lattice at several shifts
// (detail::latticeShift; the first is restingDrop's own): where the lattice lies moves a
// 3 mm drop's figure as much as its jitter does (0.85 / 0.99 / 0.95 of
// 2 sigma / R over successive 0.15 s windows of one drop). Pressure,
// radius, the constraint's share and the forces are the samplings' means;
// the time series is the first's.
Drop sampledDrop(const std::vector<Drop>& drops, const Options& options) {
    const int samplings = int(drops.size());
    const auto meanOf = [&](double Drop::*field) {
        std::vector<double> values;
        for (const Drop& d : drops) values.push_back(d.*field);
        return detail::sampleMean(values);
    };
    Drop drop = drops.front();
    drop.samplings = samplings;
    drop.radius = meanOf(&Drop::radius).mean;
    drop.constraintShare = meanOf(&Drop::constraintShare).mean;
    const detail::SampleMean pressure = meanOf(&Drop::pressure);
    drop.pressure = pressure.mean;
    drop.pressureError = pressure.standardError();
    drop.mean = {};
    for (const Drop& d : drops) drop.mean += d.mean;
    drop.mean /= samplings;
    if (options.progress)
        options.progress(fmt::format(
            "laplace: drop of {:.2f} mm, {} samplings of the lattice: pressure {:.1f} Pa (standard "
            "error {:.1f}), 2 sigma / R = {:.1f} Pa",
            1e3 * drop.radius, samplings, drop.pressure, drop.pressureError,
            2.0 * kSigma / drop.radius));
    return drop;
}

CaseResult run(const Options& options) {
    CaseResult result;
    result.name = "laplace";
    result.title =
        "Laplace pressure of resting drops, from the forces across the equator's inner disc";
    const float spacing = options.quick ? 0.0008f : 0.0005f;
    // The large drop, the study's drops (below) and the small drop's
    // samplings side by side (concurrent.hpp), the longest first.
    struct Task {
        double radius, average;
        int shift;
    };
    constexpr int kSamplings = 4;
    std::vector<Task> tasks{{0.006, kAverage, 0}};
    if (!options.quick)
        for (const double r : {0.008, 0.004, 0.0025}) tasks.push_back({r, kStudyAverage, 0});
    for (int k = 0; k < kSamplings; ++k) tasks.push_back({0.003, kAverage, k});
    const detail::SerialProgress progress(options);
    const std::vector<Drop> runs = detail::concurrently(tasks.size(), [&](std::size_t k) {
        return restingDrop(tasks[k].radius, spacing, 0, tasks[k].average, progress.options(),
                           detail::latticeShift(tasks[k].shift));
    });
    const Drop large = runs.front();
    const Drop small = sampledDrop({runs.end() - kSamplings, runs.end()}, options);
    // The small drop again at about half the capillary substep (fixed
    // substeps): quieter, and its pressure should not change if it is set
    // by sigma. Reported, not checked.
    const int halfStep = int(std::ceil(2.0 / (200.0 * small.dt)));
    const Drop quiet = restingDrop(0.003, spacing, halfStep, kAverage, options);
    // The 1 / R law over 5 to 16 spacings in radius (without --quick; not
    // checked, averaged 0.15 s): p R / 2 sigma is the drop's static
    // tension over sigma; with the curvature force it falls slowly with
    // R / d (0.98 at 6 spacings, 0.77 at 16: docs/surface_tension.md, Limits).
    const std::vector<Drop> study(runs.begin() + 1, runs.end() - kSamplings);

    plot::Panel panel{
        "Constraint's share: its force across the equator per area", "t (s)", "Pa", {}};
    for (const Drop* d : {&small, &large, &quiet}) {
        const std::string label =
            fmt::format("R = {:.2f} mm, substep {:.0f} us", 1e3 * d->radius, 1e6 * d->dt);
        panel.series.push_back(detail::record(result, label, "t_s", d->t, "Pa", d->p));
    }
    for (const Drop* d : {&small, &large})
        panel.series.push_back(
            detail::record(result, fmt::format("R = {:.2f} mm: 2 sigma / R", 1e3 * d->radius),
                           "t_s", {d->t.front(), d->t.back()}, "Pa",
                           {2 * kSigma / d->radius, 2 * kSigma / d->radius}, plot::Style::Dashed));
    plot::Panel law{
        "Static tension p R / 2 sigma against R / spacing", "R / d", "p R / (2 sigma)", {}};
    std::vector<double> across, tension;
    std::vector<const Drop*> drops{&small, &large};
    for (const Drop& d : study) drops.push_back(&d);
    std::sort(drops.begin(), drops.end(),
              [](const Drop* a, const Drop* b) { return a->radius < b->radius; });
    for (const Drop* d : drops) {
        across.push_back(d->radius / spacing);
        tension.push_back(d->pressure * d->radius / (2.0 * kSigma));
    }
    law.series.push_back(detail::record(result, "p R / 2 sigma", "R_over_d", across,
                                        "static_tension_over_sigma", tension, plot::Style::Points));
    law.series.push_back(
        detail::record(result, "Laplace", "R_over_d", {across.front(), across.back()},
                       "static_tension_over_sigma", {1.0, 1.0}, plot::Style::Dashed));
    result.figure = {"Laplace: resting drops", {panel, law}, 1};
    for (const Drop* d : {&small, &large})
        result.checks.push_back(
            {fmt::format("pressure in the {:.1f} mm drop{}", 1e3 * d->radius,
                         d->samplings > 1
                             ? fmt::format(" (mean of {} lattice samplings)", d->samplings)
                             : ""),
             d->pressure, 2.0 * kSigma / d->radius, 0.25 * 2.0 * kSigma / d->radius, "Pa",
             "Young-Laplace: 2 sigma / R",
             "25 %: the curvature force's factors are measured on the particles, not fitted "
             "(kappa and the band's integral within 5-15 % on the rest lattice), "
             "and the pair fit of the constraint's force leaves a residual of about a quarter"});
    result.checks.push_back({"p R of the small drop / p R of the large",
                             small.pressure * small.radius / (large.pressure * large.radius), 1.0,
                             0.2, "", "the 1 / R law", "both drops at the same resolution"});
    // Catches a measure that is not the constraint's force of one substep:
    // one missing a dt, a lost scale or sign. (An acceleration accumulated
    // over substeps through the warm start would read 1 / (1 - w) times too
    // high: 5 times at w = 0.8, which this check caught; at this case's
    // 1e-6 it no longer would.)
    for (const Drop* d : {&small, &large})
        result.checks.push_back(
            {fmt::format("{:.1f} mm drop: (constraint + core + kinetic) across the equator / "
                         "(cohesion pull across it + curvature force on the upper half)",
                         1e3 * d->radius),
             d->balance(), 1.0, 0.2, "", "Newton's third law on the upper half at rest",
             "20 %: the kinetic share is estimated in a slab two spacings thick, and the "
             "smallest drop (quick: 208 particles) has few particles in it"});
    // Catches a pair fit that does not reproduce the constraint's force (a
    // wrong sign, a lost scale): the per-particle sum is exact.
    for (const Drop* d : {&small, &large})
        result.checks.push_back(
            {fmt::format("{:.1f} mm drop: the pair fit's constraint force across the equator / the "
                         "per-particle sum",
                         1e3 * d->radius),
             d->fitAgreement(), 1.0, 0.25, "", "the same force, summed two ways",
             "25 %: the fit's residual (the substep's iterations move the particles between "
             "their lambdas)"});
    result.notes = fmt::format(
        "Drops of water (sigma {} N/m) without gravity, particles {:.2f} mm apart, warm start "
        "1e-6 (it records the solve acceleration; the solver's default is 0), XSPH 0.05; 0.15 s to "
        "settle, then the constraint's force across the equator "
        "averaged for 0.45 s; the 3 mm drop cut from the lattice at {} shifts and averaged. "
        "Pressure: the total stress across the equator's inner disc "
        "(r < R / 2: constraint, split pair by pair by a least-squares fit of one lambda per "
        "particle, + cohesion pull + core + momentum flux); the "
        "constraint's force across the "
        "whole equator alone: {:.1f} and {:.1f} Pa. The {:.1f} mm drop at a substep of {:.0f} "
        "us instead of {:.0f}: rms speed {:.3f} m/s instead of {:.3f}, {:.0f} surface particles "
        "instead of {:.0f}, pressure {:.1f} Pa instead of {:.1f} (the samplings' mean; "
        "constraint's share {:.1f} instead of {:.1f}; 2 sigma / R = {:.1f} Pa).",
        kSigma, 1e3 * spacing, small.samplings, small.constraintShare, large.constraintShare,
        1e3 * quiet.radius, 1e6 * quiet.dt, 1e6 * small.dt, quiet.vrms(), small.vrms(),
        quiet.mean.surface, small.mean.surface, quiet.pressure, small.pressure,
        quiet.constraintShare, small.constraintShare, 2.0 * kSigma / small.radius);
    if (!study.empty()) {
        result.notes +=
            " Static tension p R / 2 sigma (the 1 / R law, not checked; the study's drops "
            "averaged 0.15 s):";
        for (std::size_t k = 0; k < across.size(); ++k)
            result.notes += fmt::format(" {:.3f} at R / d = {:.1f}{}", tension[k], across[k],
                                        k + 1 < across.size() ? "," : ".");
    }
    return result;
}

}  // namespace

Case laplaceCase() {
    return {"laplace",
            "the pressure in resting drops (all forces across the inner disc): 2 sigma / R", run};
}

}  // namespace pbf::validation
