// Particles -> level set -> mesh with OpenVDB (steps in surface.hpp).
#include <openvdb/io/Stream.h>
#include <openvdb/openvdb.h>
#include <openvdb/tools/Interpolation.h>
#include <openvdb/tools/LevelSetFilter.h>
#include <openvdb/tools/ParticlesToLevelSet.h>
#include <openvdb/tools/PointIndexGrid.h>
#include <openvdb/tools/VolumeToMesh.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "anisotropic_grid.hpp"
#include "openvdb_particles.hpp"
#include "pbf/io/io.hpp"
#include "pbf/surface/surface.hpp"

namespace pbf::surface {

struct LevelSet::Impl {
    openvdb::FloatGrid::Ptr grid;
};

LevelSet::LevelSet() : impl_(std::make_unique<Impl>()) {}
LevelSet::~LevelSet() = default;
LevelSet::LevelSet(LevelSet&&) noexcept = default;
LevelSet& LevelSet::operator=(LevelSet&&) noexcept = default;
std::size_t LevelSet::activeVoxels() const {
    return impl_->grid ? static_cast<std::size_t>(impl_->grid->activeVoxelCount()) : 0;
}
bool LevelSet::empty() const {
    return activeVoxels() == 0;
}

namespace {

using detail::ParticleList;
using IndexGrid = openvdb::tools::PointIndexGrid;

using PointIterator = openvdb::tools::PointIndexIterator<IndexGrid::TreeType>;

// Search structure over the particles with cells of edge `cell`.
struct PointSearch {
    PointSearch(const ParticleList& list, double cell)
        : transform(openvdb::math::Transform::createLinearTransform(cell)),
          grid(openvdb::tools::createPointIndexGrid<IndexGrid>(list, *transform)) {}

    // Calls visit(i, it) for every particle i of `list`, in parallel, with
    // `it` over the particles within `radius` of it (i included).
    template <class Visit>
    void forEachNear(const ParticleList& list, double radius, Visit&& visit) const {
        tbb::parallel_for(tbb::blocked_range<std::size_t>(0, list.size()), [&](const auto& range) {
            auto accessor = grid->getConstAccessor();
            PointIterator it;
            openvdb::Vec3R p;
            for (std::size_t i = range.begin(); i != range.end(); ++i) {
                list.getPos(i, p);
                it.worldSpaceSearchAndUpdate(p, radius, accessor, list, *transform);
                visit(i, it);
            }
        });
    }

    openvdb::math::Transform::Ptr transform;
    IndexGrid::Ptr grid;
};

// Number of other particles within `radius` of each particle.
std::vector<int> countNeighbors(const ParticleList& list, double radius) {
    const PointSearch search(list, radius);
    std::vector<int> counts(list.size());
    search.forEachNear(list, radius, [&](std::size_t i, const PointIterator& it) {
        counts[i] = static_cast<int>(it.size()) - 1;  // minus the particle itself
    });
    return counts;
}

// Mean height, in particle radii, of the top of a union of spheres of radius
// `scale` r centred on a flat square layer of spacing 2 r, above the centres
// (midpoint rule over one lattice cell, where the nearest centre is the
// cell's own). Eroding by this height minus 1 puts a flat water surface, on
// average, one radius above the top particles: its volume is then the
// particles' volume, which a plain erosion by (scale - 1) r undershoots
// because the union sags between the spheres.
double meanUnionHeight(double scale) {
    constexpr int kSamples = 64;
    double sum = 0.0;
    for (int i = 0; i < kSamples; ++i)
        for (int j = 0; j < kSamples; ++j) {
            const double x = -1.0 + (i + 0.5) * 2.0 / kSamples,
                         y = -1.0 + (j + 0.5) * 2.0 / kSamples;
            sum += std::sqrt(std::max(0.0, scale * scale - x * x - y * y));
        }
    return sum / (kSamples * kSamples);
}

void requireValid(const SurfaceParams& params) {
    if (const std::string problem = validate(params); !problem.empty())
        throw std::invalid_argument(problem);
}

}  // namespace

const char* toString(SurfaceMethod method) {
    return method == SurfaceMethod::isotropic ? "isotropic" : "anisotropic";
}

SurfaceMethod parseSurfaceMethod(std::string_view text) {
    if (text == "isotropic") return SurfaceMethod::isotropic;
    if (text == "anisotropic") return SurfaceMethod::anisotropic;
    throw std::invalid_argument("method: must be isotropic or anisotropic, got '" +
                                std::string(text) + "'");
}

std::string validate(const SurfaceParams& p) {
    if (!(p.particleRadius > 0.0f && std::isfinite(p.particleRadius)))
        return "radius: the particle radius must be positive, got " +
               std::to_string(p.particleRadius);
    const auto inRange = [](float v, float lo, float hi) { return v >= lo && v <= hi; };
    if (!inRange(p.kernelRadius, 2.0f, 8.0f))
        return "kernel-radius: must be in [2, 8] particle radii, got " +
               std::to_string(p.kernelRadius);
    if (!inRange(p.neighborRadius, 2.0f, 12.0f))
        return "neighbor-radius: must be in [2, 12] particle radii, got " +
               std::to_string(p.neighborRadius);
    if (!inRange(p.centreSmoothing, 0.0f, 1.0f))
        return "centre-smoothing: must be in [0, 1], got " + std::to_string(p.centreSmoothing);
    if (!inRange(p.maxAnisotropy, 1.0f, 16.0f))
        return "max-anisotropy: must be in [1, 16], got " + std::to_string(p.maxAnisotropy);
    if (!inRange(p.isolatedScale, 0.25f, 1.0f))
        return "isolated-scale: must be in [0.25, 1], got " + std::to_string(p.isolatedScale);
    if (p.anisotropyMinNeighbors < 1 || p.anisotropyMinNeighbors > 200)
        return "anisotropy-neighbors: must be in [1, 200], got " +
               std::to_string(p.anisotropyMinNeighbors);
    if (p.anisotropicSmoothing < 0 || p.anisotropicSmoothing > 100)
        return "smooth: must be in [0, 100], got " + std::to_string(p.anisotropicSmoothing);
    // The smallest kernel (k_n h across, or h / k_r across a sheet) must
    // span a few voxels or the field aliases on the grid.
    if (p.method == SurfaceMethod::anisotropic && p.voxelSize > 0.0f &&
        p.kernelRadius * std::min(p.isolatedScale, 1.0f / p.maxAnisotropy) < 0.75f * p.voxelSize)
        return "voxel-size: must be at most 4 / 3 of the smallest kernel axis (kernel-radius x "
               "min(isolated-scale, 1 / max-anisotropy)), got " +
               std::to_string(p.voxelSize);
    if (!(p.voxelSize > 0.0f && p.voxelSize <= 2.0f))
        return "voxel-size: must be in (0, 2] particle radii, got " + std::to_string(p.voxelSize);
    // Below sqrt(2) the spheres of a flat layer leave holes: no closing.
    if (!(p.sphereScale >= 1.5f && p.sphereScale <= 4.0f))
        return "sphere-scale: must be in [1.5, 4], got " + std::to_string(p.sphereScale);
    // ParticlesToLevelSet skips spheres narrower than 1.5 voxels.
    if (p.sphereScale < 1.5f * p.voxelSize)
        return "voxel-size: must be at most sphere-scale / 1.5 = " +
               std::to_string(p.sphereScale / 1.5f) +
               " particle radii (OpenVDB skips spheres narrower than 1.5 voxels)";
    if (p.smoothing < 0 || p.smoothing > 100)
        return "smooth: must be in [0, 100], got " + std::to_string(p.smoothing);
    if (p.minNeighbors < 0 || p.minNeighbors > 1000)
        return "min-neighbors: must be in [0, 1000], got " + std::to_string(p.minNeighbors);
    if (!(p.adaptivity >= 0.0f && p.adaptivity <= 1.0f))
        return "adaptivity: must be in [0, 1], got " + std::to_string(p.adaptivity);
    return {};
}

LevelSet buildLevelSet(std::span<const Vec3> positions, const SurfaceParams& params,
                       BuildReport* report) {
    requireValid(params);
    openvdb::initialize();
    const double r = params.particleRadius;
    const double dx = params.voxelSize * r;

    // 1. Spray filter: 4 r is the PBF kernel support (about 33 neighbours in
    // the bulk, ~15 at a flat surface, 0-3 for a lone droplet).
    std::vector<Vec3> kept;
    std::span<const Vec3> meshed = positions;
    if (params.minNeighbors > 0 && !positions.empty()) {
        const std::vector<int> counts = countNeighbors(ParticleList(positions), 4.0 * r);
        kept.reserve(positions.size());
        for (std::size_t i = 0; i < positions.size(); ++i)
            if (counts[i] >= params.minNeighbors) kept.push_back(positions[i]);
        meshed = kept;
    }
    if (report) {
        report->particles = positions.size();
        report->sprayDropped = positions.size() - meshed.size();
    }

    if (params.method == SurfaceMethod::anisotropic) {
        LevelSet result;
        result.impl().grid = detail::anisotropicLevelSet(meshed, params, dx, 3.0f);
        if (meshed.empty()) return result;
        openvdb::tools::LevelSetFilter<openvdb::FloatGrid> filter(*result.impl().grid);
        filter.setSpatialScheme(openvdb::math::FIRST_BIAS);
        filter.setTemporalScheme(openvdb::math::TVD_RK1);
        // The field is smooth already; a pass or two of mean-curvature flow
        // takes out the voxel-scale ripples of the rebuilt distance field.
        for (int k = 0; k < params.anisotropicSmoothing; ++k) filter.meanCurvature();
        openvdb::tools::pruneLevelSet(result.impl().grid->tree());
        return result;
    }

    // The band must hold the erosion distance plus the stencils of the
    // smoothing filter.
    const double erosion = (meanUnionHeight(params.sphereScale) - 1.0) * r;
    const float halfWidth = static_cast<float>(std::max(3.0, std::ceil(erosion / dx) + 2.0));
    LevelSet result;
    openvdb::FloatGrid::Ptr grid = openvdb::createLevelSet<openvdb::FloatGrid>(dx, halfWidth);
    grid->setName("surface");
    result.impl().grid = grid;
    if (meshed.empty()) return result;

    // 2. Union of enlarged spheres.
    openvdb::tools::ParticlesToLevelSet<openvdb::FloatGrid> raster(*grid);
    raster.rasterizeSpheres(ParticleList(meshed), params.sphereScale * r);
    raster.finalize(/*prune=*/true);

    openvdb::tools::LevelSetFilter<openvdb::FloatGrid> filter(*grid);
    // The tracker re-normalises the band after every filter step. Its
    // default (fifth-order WENO, 19-point stencil) dominated the run time;
    // a first-order upwind gradient is ample for a band that is re-made
    // from a smoothed surface, and about three times cheaper.
    filter.setSpatialScheme(openvdb::math::FIRST_BIAS);
    filter.setTemporalScheme(openvdb::math::TVD_RK1);
    // 3. Erode back (a positive offset moves the zero crossing inwards).
    if (erosion > 0.0) filter.offset(static_cast<float>(erosion));
    // The erosion needed the wide band; smoothing needs only the standard
    // three voxels, and every filter pass costs in proportion to the band.
    filter.resize(3);
    // 4. Mean-curvature flow: speed proportional to curvature, so single
    // sphere bumps (high curvature) go first and flat water stays put.
    for (int k = 0; k < params.smoothing; ++k) filter.meanCurvature();
    openvdb::tools::pruneLevelSet(grid->tree());
    return result;
}

namespace {

// Unit normals at the mesh vertices from the level set's gradient (central
// differences one voxel either side, trilinear samples): the normal of the
// smooth surface the mesh approximates, so a smooth-shaded mesh looks as
// smooth as the level set, not faceted like averaged triangle normals.
std::vector<Vec3> levelSetNormals(const openvdb::FloatGrid& grid,
                                  const std::vector<openvdb::Vec3s>& points) {
    std::vector<Vec3> normals(points.size());
    const double d = grid.voxelSize()[0];
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size()), [&](const auto& range) {
        // GridSampler keeps a reference to the accessor: it must outlive the
        // sampler (a temporary here was a stack-use-after-scope under ASan).
        const openvdb::FloatGrid::ConstAccessor accessor = grid.getConstAccessor();
        const openvdb::tools::GridSampler<openvdb::FloatGrid::ConstAccessor,
                                          openvdb::tools::BoxSampler>
            phi(accessor, grid.transform());
        for (std::size_t i = range.begin(); i != range.end(); ++i) {
            const openvdb::Vec3d p = points[i];
            const openvdb::Vec3d g(phi.wsSample(p + openvdb::Vec3d(d, 0, 0)) -
                                       phi.wsSample(p - openvdb::Vec3d(d, 0, 0)),
                                   phi.wsSample(p + openvdb::Vec3d(0, d, 0)) -
                                       phi.wsSample(p - openvdb::Vec3d(0, d, 0)),
                                   phi.wsSample(p + openvdb::Vec3d(0, 0, d)) -
                                       phi.wsSample(p - openvdb::Vec3d(0, 0, d)));
            const double length = g.length();
            // A zero gradient (a vertex where two sheets meet) has no normal;
            // +y keeps the file valid, and it happens on too few vertices to show.
            normals[i] = length > 0.0 ? Vec3{float(g.x() / length), float(g.y() / length),
                                             float(g.z() / length)}
                                      : Vec3{0.0f, 1.0f, 0.0f};
        }
    });
    return normals;
}

}  // namespace

TriangleMesh extractMesh(const LevelSet& levelSet, float adaptivity) {
    TriangleMesh mesh;
    const openvdb::FloatGrid::Ptr& grid = levelSet.impl().grid;
    if (!grid || grid->activeVoxelCount() == 0) return mesh;
    std::vector<openvdb::Vec3s> points;
    std::vector<openvdb::Vec3I> triangles;
    std::vector<openvdb::Vec4I> quads;
    openvdb::tools::volumeToMesh(*grid, points, triangles, quads, 0.0, adaptivity);

    mesh.vertices.reserve(points.size());
    for (const openvdb::Vec3s& p : points) mesh.vertices.push_back({p.x(), p.y(), p.z()});
    mesh.normals = levelSetNormals(*grid, points);
    mesh.triangles.reserve(triangles.size() + 2 * quads.size());
    // OpenVDB orders polygons clockwise seen from outside (Houdini's
    // convention); reverse them to the counter-clockwise order OBJ/PLY
    // readers take as front-facing.
    for (const openvdb::Vec3I& t : triangles) mesh.triangles.push_back({t[2], t[1], t[0]});
    for (const openvdb::Vec4I& q : quads) {
        mesh.triangles.push_back({q[2], q[1], q[0]});
        mesh.triangles.push_back({q[3], q[2], q[0]});
    }
    return mesh;
}

TriangleMesh reconstructSurface(std::span<const Vec3> positions, const SurfaceParams& params,
                                BuildReport* report) {
    return extractMesh(buildLevelSet(positions, params, report), params.adaptivity);
}

void writeLevelSetVdb(const std::filesystem::path& path, const LevelSet& levelSet) {
    openvdb::initialize();
    const openvdb::FloatGrid::Ptr& grid = levelSet.impl().grid;
    if (!grid) throw IoError(path.string() + ": no level set to write");
    writeFileAtomically(path, [&](std::ostream& out) {
        openvdb::io::Stream stream(out);
        stream.write(openvdb::GridCPtrVec{grid});
    });
}

float estimateParticleRadius(std::span<const Vec3> positions) {
    if (positions.size() < 2)
        throw std::invalid_argument(
            "cannot estimate the particle radius from fewer than 2 particles");
    openvdb::initialize();
    Vec3 lo = positions[0], hi = positions[0];
    for (const Vec3& p : positions) {
        lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
        hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
    }
    const Vec3 e = hi - lo;
    const double n = double(positions.size());
    // Spacing if the particles filled their bounding box evenly (an upper
    // bound for the bulk); fall back to the largest extent for flat sets.
    double radius = std::cbrt(double(e.x) * e.y * e.z / n);
    if (!(radius > 0.0)) radius = std::max({e.x, e.y, e.z}) / std::sqrt(n);
    if (!(radius > 0.0))
        throw std::invalid_argument("cannot estimate the particle radius: all particles coincide");

    const ParticleList list(positions);
    for (int attempt = 0; attempt < 30; ++attempt, radius *= 2.0) {
        const PointSearch search(list, radius);
        std::vector<float> nearest(positions.size(), -1.0f);
        search.forEachNear(list, radius, [&](std::size_t i, PointIterator& it) {
            float best = -1.0f;
            for (; it; ++it) {
                if (*it == i) continue;
                const float d = length(positions[*it] - positions[i]);
                if (d > 0.0f && (best < 0.0f || d < best)) best = d;
            }
            nearest[i] = best;
        });
        std::erase_if(nearest, [](float d) { return d < 0.0f; });
        // Most particles must see a neighbour, or the median describes spray.
        if (nearest.size() * 2 < positions.size()) continue;
        auto middle = nearest.begin() + static_cast<std::ptrdiff_t>(nearest.size() / 2);
        std::nth_element(nearest.begin(), middle, nearest.end());
        return 0.5f * *middle;
    }
    throw std::invalid_argument("cannot estimate the particle radius: particles are too scattered");
}

}  // namespace pbf::surface
