// Laplace (1806), Young (1805): the pressure inside a resting drop exceeds
// the outside's by 2 sigma / R. PBF has no pressure variable, but its
// density constraint exerts one: the position corrections of a substep,
// divided by dt^2, are the constraint's force per mass, and pair by pair
// they are equal and opposite (lambda_i + lambda_j, antisymmetric kernel
// gradient). Summed over the particles above the drop's equator, the
// corrections inside the upper half cancel and what remains is the force
// the lower half's water exerts across the equatorial disc: the pressure
// times pi R^2 (outside is empty). The cohesion acts only in the surface
// layer, so at rest this is the Laplace pressure, and it must scale as
// 1 / R. Measured with the warm start on (it records each particle's
// correction per dt^2, the solve acceleration), averaged over many frames
// of two resting drops.
#include <fmt/format.h>

#include <cmath>
#include <numbers>

#include "validate/drops.hpp"
#include "validate/measure.hpp"

namespace pbf::validation {
namespace {

constexpr double kSigma = 0.0728;

struct Drop {
    double radius = 0.0;    // from the particles' volume, m
    double pressure = 0.0;  // Pa, averaged
    std::size_t particles = 0;
    std::vector<double> t, p;
};

Drop restingDrop(double radius, float spacing, const Options& options) {
    WorldDef def = detail::waterWorld(0.5f * spacing, float(5.0 * radius), float(kSigma));
    def.name = "laplace";
    def.simulation.solver.warmStart = 0.8f;  // records the solve acceleration
    def.simulation.fluid.viscosity = 0.05f;  // the drop comes to rest
    def.fps = 200.0f;
    const float half = 0.5f * spacing;
    const float reach = float(radius) + spacing;
    const std::vector<Vec3> sites = detail::latticeSites(
        def, {{-reach, -reach, -reach}, {reach, reach, reach}}, {half, half, half},
        [&](const Vec3& x) { return length(x) <= float(radius); });
    World world = detail::worldOf(def, sites);
    Drop drop;
    drop.particles = world.particleCount();
    drop.radius = std::cbrt(3.0 * double(drop.particles) / (4.0 * std::numbers::pi)) * spacing;
    const double settle = 0.15, average = 0.15;  // s: a few capillary times of these drops
    const double m = world.constants().particleMass;
    double sum = 0.0;
    int samples = 0;
    while (world.time() < settle + average - 1e-9) {
        detail::step(world);
        const ParticleStore& p = world.particles();
        const Vec3 c = detail::centroid(detail::positions(world));
        double force = 0.0;
        for (std::size_t i = 0; i < p.size(); ++i)
            if (p.position.y[i] > c.y) force += m * p.solveAcceleration.y[i];
        const double pressure = force / (std::numbers::pi * drop.radius * drop.radius);
        drop.t.push_back(world.time());
        drop.p.push_back(pressure);
        if (world.time() > settle) {
            sum += pressure;
            ++samples;
        }
    }
    drop.pressure = sum / samples;
    if (options.progress)
        options.progress(fmt::format(
            "laplace: drop of {:.2f} mm ({} particles): pressure {:.1f} Pa, 2 sigma / R = {:.1f} "
            "Pa",
            1e3 * drop.radius, drop.particles, drop.pressure, 2.0 * kSigma / drop.radius));
    return drop;
}

CaseResult run(const Options& options) {
    CaseResult result;
    result.name = "laplace";
    result.title = "Laplace pressure of resting drops, from the density constraint's forces";
    const float spacing = options.quick ? 0.0008f : 0.0005f;
    const Drop small = restingDrop(0.003, spacing, options);
    const Drop large = restingDrop(0.006, spacing, options);

    plot::Panel panel{"Pressure across the equator", "t (s)", "pressure (Pa)", {}};
    for (const Drop* d : {&small, &large}) {
        const std::string label = fmt::format("R = {:.2f} mm", 1e3 * d->radius);
        panel.series.push_back(detail::record(result, label, "t_s", d->t, "Pa", d->p));
        panel.series.push_back(detail::record(
            result, label + ": 2 sigma / R", "t_s", {d->t.front(), d->t.back()}, "Pa",
            {2 * kSigma / d->radius, 2 * kSigma / d->radius}, plot::Style::Dashed));
    }
    result.figure = {result.title, {panel}, 1};
    for (const Drop* d : {&small, &large})
        result.checks.push_back(
            {fmt::format("pressure in the {:.1f} mm drop", 1e3 * d->radius), d->pressure,
             2.0 * kSigma / d->radius, 0.25 * 2.0 * kSigma / d->radius, "Pa",
             "Young-Laplace: 2 sigma / R",
             "25 %: sigma is calibrated on the Rayleigh frequency (within 10 %), and the "
             "constraint's force fluctuates with the surface particles' noise"});
    result.checks.push_back({"p R of the small drop / p R of the large",
                             small.pressure * small.radius / (large.pressure * large.radius), 1.0,
                             0.2, "", "the 1 / R law", "both drops at the same resolution"});
    result.notes = fmt::format(
        "Drops of water (sigma {} N/m) without gravity, particles {:.2f} mm apart, warm start "
        "0.8, XSPH 0.05; 0.15 s to settle, then the constraint's force across the equator "
        "averaged for 0.15 s.",
        kSigma, 1e3 * spacing);
    return result;
}

}  // namespace

Case laplaceCase() {
    return {"laplace", "the density constraint's pressure in resting drops: 2 sigma / R", run};
}

}  // namespace pbf::validation
