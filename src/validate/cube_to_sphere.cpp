// Zero gravity: a cube of water pulled together by surface tension alone
// becomes a sphere (the shape of least area for its volume) and stays one:
// no particles leave it, and the cohesion does not pull particles into
// clusters (its kernel is repulsive below ~0.27 h, and the density
// constraint keeps the spacing). Measured: Wadell's sphericity
// pi^(1/3) (6 V)^(2/3) / A of the reconstructed surface (1 for a sphere,
// 0.806 for a cube), the number of connected pieces, and how close
// particles come: the smallest pair distance (reported) and, checked, the
// nearest-neighbour distance that 99 % of the particles keep (kClusterShare).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "pbf/surface/mesh.hpp"
#include "pbf/surface/surface.hpp"
#include "validate/drops.hpp"
#include "validate/measure.hpp"

namespace pbf::validation {
namespace {

constexpr double kSigma = 0.0728;
constexpr double kRho = 1000.0;
constexpr double kSide = 0.01;  // m
// Clustering is a share of the particles sitting on a neighbour, not one
// pair: the drop's particles jitter (0.1-0.3 m/s), and two of them meeting
// for a substep is a collision the core resolves. Without the core 200 of
// 4,096 particles (5 %) were within half a spacing of another; the smallest
// pair alone was 0.54 spacings in release and 0.49 under -O2 with
// sanitizers on the same run (a single collision deciding the check). So
// the check asks that 99 % of the particles keep their nearest neighbour
// beyond half a spacing at every frame: it fails where 1 % cluster.
constexpr double kClusterShare = 0.01;

// The nearest-neighbour distance that all but kClusterShare of the
// particles keep, in spacings.
double clusterDistance(const std::vector<Vec3>& x, float reach, float spacing) {
    std::vector<double> nearest = detail::nearestNeighborDistances(x, reach);
    const auto k = std::ptrdiff_t(kClusterShare * double(nearest.size()));
    std::nth_element(nearest.begin(), nearest.begin() + k, nearest.end());
    return nearest[std::size_t(k)] / spacing;
}

// Wadell's sphericity of the particles' reconstructed surface.
double sphericity(const std::vector<Vec3>& x, float radius) {
    surface::SurfaceParams params;
    params.particleRadius = radius;
    params.method = surface::SurfaceMethod::isotropic;
    const surface::TriangleMesh mesh = surface::reconstructSurface(x, params);
    const double volume = std::fabs(surface::meshVolume(mesh)), area = surface::meshArea(mesh);
    if (!(area > 0.0)) return 0.0;
    return std::cbrt(std::numbers::pi) * std::pow(6.0 * volume, 2.0 / 3.0) / area;
}

// The measure's ceiling at this particle size: the sphericity of a ball of
// the drop's volume cut from the same lattice, at rest (its surface is as
// smooth as particles of this size allow; a drop's jitter roughens it).
double latticeBallSphericity(const WorldDef& def, std::size_t particles, float spacing) {
    const double r = std::cbrt(3.0 * double(particles) / (4.0 * std::numbers::pi)) * spacing;
    const float reach = float(r) + spacing, half = 0.5f * spacing;
    const std::vector<Vec3> ball = detail::latticeSites(
        def, {{-reach, -reach, -reach}, {reach, reach, reach}}, {half, half, half},
        [&](const Vec3& x) {
            return double(x.x) * x.x + double(x.y) * x.y + double(x.z) * x.z <= r * r;
        });
    return sphericity(ball, def.simulation.particleRadius);
}

CaseResult run(const Options& options) {
    CaseResult result;
    result.name = "cube_to_sphere";
    result.title = "Zero gravity: a cube of water becomes a sphere";
    const int across = options.quick ? 10 : 16;
    const float spacing = float(kSide / across);
    const float radius = 0.5f * spacing;
    WorldDef def = detail::waterWorld(radius, float(3.0 * kSide), float(kSigma));
    def.name = "cube_to_sphere";
    const float half = float(0.5 * kSide);
    def.fluidBlocks.push_back({{{-half, -half, -half}, {half, half, half}}, {}});
    // The capillary time sqrt(rho L^3 / sigma) (0.12 s): the cube's corners
    // round in about one, the drop rings down in a few.
    const double capillaryTime = std::sqrt(kRho * std::pow(kSide, 3) / kSigma);
    const double duration = 6.0 * capillaryTime;
    def.fps = float(20.0 / capillaryTime);
    World world(def);
    const float h = world.constants().h;

    std::vector<double> t, psi, pieces, closest, cluster;
    auto sample = [&](bool withSurface) {
        const std::vector<Vec3> x = detail::positions(world);
        t.push_back(world.time());
        pieces.push_back(double(detail::clusterCount(x, h)));
        closest.push_back(detail::smallestPairDistance(x, h) / spacing);
        cluster.push_back(clusterDistance(x, h, spacing));
        psi.push_back(withSurface ? sphericity(x, radius) : std::nan(""));
    };
    sample(true);
    const double initial = psi.front();
    int frame = 0;
    while (world.time() < duration - 1e-9) {
        detail::step(world);
        sample(++frame % 4 == 0 || world.time() >= duration - 1e-9);
    }
    // The last third: the drop has rung down (a sphere that stays one).
    double worstLate = 1.0, mostPieces = 0.0, smallest = 1e9, clustered = 1e9;
    std::vector<double> tSurface, psiSurface;
    for (std::size_t k = 0; k < t.size(); ++k) {
        mostPieces = std::max(mostPieces, pieces[k]);
        smallest = std::min(smallest, closest[k]);
        clustered = std::min(clustered, cluster[k]);
        if (std::isnan(psi[k])) continue;
        tSurface.push_back(t[k]);
        psiSurface.push_back(psi[k]);
        if (t[k] >= 2.0 / 3.0 * duration) worstLate = std::min(worstLate, psi[k]);
    }
    const double ceiling = latticeBallSphericity(def, world.particleCount(), spacing);
    if (options.progress)
        options.progress(fmt::format(
            "cube_to_sphere: {} particles, sphericity {:.3f} -> {:.3f} (lowest over the last "
            "third {:.3f}; a ball cut from the lattice reads {:.3f}), pieces <= {:.0f}, closest "
            "pair {:.2f} spacings, 99 % of the particles' nearest neighbour >= {:.2f} spacings",
            world.particleCount(), initial, psi.back(), worstLate, ceiling, mostPieces, smallest,
            clustered));

    plot::Panel shape{"Sphericity of the reconstructed surface", "t (s)", "sphericity", {}};
    shape.series.push_back(detail::record(result, "sphericity", "t_s", tSurface, "sphericity",
                                          psiSurface, plot::Style::Points));
    shape.series.push_back(detail::record(result, "required", "t_s", {t.front(), t.back()},
                                          "sphericity", {0.95, 0.95}, plot::Style::Dashed));
    shape.series.push_back(detail::record(result, "a ball cut from the lattice, at rest", "t_s",
                                          {t.front(), t.back()}, "sphericity", {ceiling, ceiling},
                                          plot::Style::Dashed));
    plot::Panel spacingPanel{"Closest pair of particles", "t (s)", "distance / spacing", {}};
    spacingPanel.series.push_back(
        detail::record(result, "closest pair", "t_s", t, "spacings", closest));
    spacingPanel.series.push_back(
        detail::record(result, "nearest neighbour, 1st percentile", "t_s", t, "spacings", cluster));
    result.figure = {result.title, {shape, spacingPanel}, 2};

    result.checks.push_back(
        {"lowest sphericity over the last third", worstLate, 0.95, 0.0, "",
         "a sphere (1); the cube starts at " + fmt::format("{:.3f}", initial),
         ">= 0.95: a particle surface is rough at the scale of a spacing, which "
         "keeps even a resting drop's reconstructed sphericity below 1",
         Check::Bound::AtLeast});
    result.checks.push_back({"most pieces at any frame", mostPieces, 1.0, 0.0, "",
                             "one drop (particles linked closer than h)",
                             "no particle may leave the drop", Check::Bound::AtMost});
    result.checks.push_back(
        {"nearest neighbour kept by 99 % of the particles / spacing", clustered, 0.5, 0.0, "",
         "no clustering",
         "above half a spacing at every frame: cohesion alone would pull pairs "
         "together where the constraint is inactive (5 % of the particles did without the "
         "core); 1 % may meet in a collision",
         Check::Bound::AtLeast});
    result.notes = fmt::format(
        "A {:.0f} mm cube of water ({} particles, {} across) without gravity, sigma = {} N/m, "
        "followed for {:.2f} s (6 capillary times sqrt(rho L^3 / sigma)). Sphericity is "
        "Wadell's pi^(1/3) (6 V)^(2/3) / A of the isotropic surface reconstruction "
        "(docs/surfaces.md); a ball of the drop's volume cut from the same lattice, at rest, "
        "reads {:.3f} by it (the ceiling at this particle size: the drop's jitter roughens its "
        "surface below it). Closest pair at any frame {:.2f} spacings (not checked: one "
        "collision).",
        1e3 * kSide, world.particleCount(), across, kSigma, duration, ceiling, smallest);
    return result;
}

}  // namespace

Case cubeToSphereCase() {
    return {"cube_to_sphere", "zero gravity: a cube of water becomes a sphere and stays one", run};
}

}  // namespace pbf::validation
