// Triangle-mesh solids: OBJ meshes (pbf::loadTriangleMesh) turned into a narrow-band signed
// distance field built by OpenVDB (tools::meshToLevelSet; Bridson-style
// closest-triangle distances with inside/outside from a flood fill).
#include <openvdb/openvdb.h>
#include <openvdb/tools/MeshToVolume.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <map>
#include <mutex>
#include <optional>
#include <utility>

#include "geometry/shape_distance.hpp"
#include "pbf/geometry/solids.hpp"
#include "pbf/geometry/triangle_mesh.hpp"

namespace pbf {
namespace {

constexpr std::size_t kMaxTriangles = 10'000'000;

[[noreturn]] void fail(const std::filesystem::path& file, const std::string& message) {
    throw SolidError(file.string() + ": " + message);
}

class MeshSolid final : public Solid {
  public:
    MeshSolid(openvdb::FloatGrid::Ptr grid, Aabb bounds, std::string description,
              float shellHalfThickness)
        : grid_(std::move(grid)),
          bounds_(bounds),
          description_(std::move(description)),
          shellHalfThickness_(shellHalfThickness),
          serial_(++serialCounter) {}

    float signedDistance(const Vec3& p, Vec3& normal) const override {
        // Trilinear interpolation of the 8 surrounding voxels gives the
        // distance and, differentiated, its gradient in one set of lookups.
        // Each thread keeps a cached tree accessor (voxels of neighbouring
        // queries share leaf nodes).
        // Keyed by a serial number, not the address: a new solid may reuse
        // the address of a destroyed one whose tree the accessor points into.
        thread_local std::uint64_t owner = 0;
        thread_local std::optional<openvdb::FloatGrid::ConstAccessor> accessor;
        if (owner != serial_ || !accessor) {
            accessor.emplace(grid_->getConstAccessor());
            owner = serial_;
        }
        const openvdb::Vec3d index = grid_->transform().worldToIndex(openvdb::Vec3d(p.x, p.y, p.z));
        const openvdb::Coord base(static_cast<int>(std::floor(index.x())),
                                  static_cast<int>(std::floor(index.y())),
                                  static_cast<int>(std::floor(index.z())));
        const float fx = static_cast<float>(index.x() - base.x());
        const float fy = static_cast<float>(index.y() - base.y());
        const float fz = static_cast<float>(index.z() - base.z());
        float v[2][2][2];
        for (int a = 0; a < 2; ++a)
            for (int b = 0; b < 2; ++b)
                for (int c = 0; c < 2; ++c) v[a][b][c] = accessor->getValue(base.offsetBy(a, b, c));
        Vec3 g;
        float d = shape::trilinearWithGradient(v, fx, fy, fz, g);
        if (shellHalfThickness_ > 0.0f) d -= shellHalfThickness_;  // open mesh: a shell
        normal = shape::normalised(g);
        return d;
    }
    Aabb bounds() const override { return bounds_; }
    std::string describe() const override { return description_; }
    // The level set's voxel values over the bounds (which include the band)
    // and one voxel more: trilinear interpolation of them is the
    // signedDistance above (beyond them the level set holds its background).
    ShapeData shapeData(float, float) const override {
        const double voxel = grid_->voxelSize()[0];
        const openvdb::Coord lo(int(std::floor(bounds_.min.x / voxel)) - 1,
                                int(std::floor(bounds_.min.y / voxel)) - 1,
                                int(std::floor(bounds_.min.z / voxel)) - 1);
        const openvdb::Coord hi(int(std::ceil(bounds_.max.x / voxel)) + 1,
                                int(std::ceil(bounds_.max.y / voxel)) + 1,
                                int(std::ceil(bounds_.max.z / voxel)) + 1);
        ShapeData d;
        d.kind = ShapeData::Kind::Samples;
        d.spacing = float(voxel);
        d.origin = {float(lo.x() * voxel), float(lo.y() * voxel), float(lo.z() * voxel)};
        d.nx = hi.x() - lo.x() + 1;
        d.ny = hi.y() - lo.y() + 1;
        d.nz = hi.z() - lo.z() + 1;
        d.values.resize(std::size_t(d.nx) * d.ny * d.nz);
        const openvdb::FloatGrid::ConstAccessor accessor = grid_->getConstAccessor();
        for (int k = 0; k < d.nz; ++k)
            for (int j = 0; j < d.ny; ++j)
                for (int i = 0; i < d.nx; ++i)
                    d.values[(std::size_t(k) * d.ny + j) * d.nx + i] =
                        accessor.getValue(lo.offsetBy(i, j, k));
        d.outside = grid_->background() - shellHalfThickness_;
        d.offset = shellHalfThickness_;
        return d;
    }

  private:
    openvdb::FloatGrid::Ptr grid_;
    Aabb bounds_;
    std::string description_;
    float shellHalfThickness_;
    std::uint64_t serial_;
    static inline std::atomic<std::uint64_t> serialCounter{0};
};

}  // namespace

std::unique_ptr<Solid> loadMeshSolid(const std::filesystem::path& file, const Transform& transform,
                                     const MeshSolidOptions& options, MeshInfo* info,
                                     double maxVoxels) {
    if (!(options.voxelSize > 0.0f) || !(options.bandWidth > 0.0f))
        fail(file, "invalid voxel size or band");
    // Reading, placement and validation are shared with the renderer.
    const TriangleMesh mesh = loadTriangleMesh(file, transform);
    if (mesh.triangles.size() > kMaxTriangles)
        fail(file,
             "more than " + std::to_string(kMaxTriangles) + " triangles; decimate the mesh first");

    std::vector<openvdb::Vec3s> points;
    points.reserve(mesh.vertices.size());
    Aabb bounds{{1e30f, 1e30f, 1e30f}, {-1e30f, -1e30f, -1e30f}};
    for (const Vec3& p : mesh.vertices) {
        points.emplace_back(p.x, p.y, p.z);
        bounds.min = {std::min(bounds.min.x, p.x), std::min(bounds.min.y, p.y),
                      std::min(bounds.min.z, p.z)};
        bounds.max = {std::max(bounds.max.x, p.x), std::max(bounds.max.y, p.y),
                      std::max(bounds.max.z, p.z)};
    }
    std::vector<openvdb::Vec3I> triangles;
    triangles.reserve(mesh.triangles.size());
    double area = 0.0;
    std::map<std::pair<unsigned, unsigned>, unsigned> edgeUse;
    for (const auto& t : mesh.triangles) {
        triangles.emplace_back(t[0], t[1], t[2]);
        for (int c = 0; c < 3; ++c) ++edgeUse[std::minmax(t[c], t[(c + 1) % 3])];
        const openvdb::Vec3s a = points[t[1]] - points[t[0]], b = points[t[2]] - points[t[0]];
        area += 0.5 * double(a.cross(b).length());
    }

    MeshInfo meshInfo;
    meshInfo.vertices = points.size();
    meshInfo.triangles = triangles.size();
    for (const auto& [edge, uses] : edgeUse) {
        if (uses == 1) ++meshInfo.boundaryEdges;
        if (uses > 2) ++meshInfo.nonManifoldEdges;
    }
    if (info) *info = meshInfo;

    const float voxel = options.voxelSize;
    const float halfWidth = std::max(3.0f, std::ceil(options.bandWidth / voxel) + 1.0f);
    const double estimatedVoxels = (area / (double(voxel) * voxel) + 1.0) * 2.0 * halfWidth;
    if (estimatedVoxels > maxVoxels)
        fail(file, "the distance field would need about " +
                       std::to_string(static_cast<long long>(estimatedVoxels)) +
                       " voxels at voxel size " + std::to_string(voxel) +
                       " m; scale the mesh down or use larger particles");

    static std::once_flag initialised;
    std::call_once(initialised, [] { openvdb::initialize(); });
    const openvdb::math::Transform::Ptr xform =
        openvdb::math::Transform::createLinearTransform(voxel);
    openvdb::FloatGrid::Ptr grid;
    float shellHalfThickness = 0.0f;
    if (meshInfo.closed()) {
        grid = openvdb::tools::meshToLevelSet<openvdb::FloatGrid>(*xform, points, triangles,
                                                                  halfWidth);
    } else {
        // No inside to flood-fill: use the unsigned distance and a shell.
        std::vector<openvdb::Vec4I> quads;
        grid = openvdb::tools::meshToUnsignedDistanceField<openvdb::FloatGrid>(
            *xform, points, triangles, quads, halfWidth);
        shellHalfThickness = std::max(0.5f * options.shellThickness, 0.5f * voxel);
    }
    const Vec3 pad{options.bandWidth, options.bandWidth, options.bandWidth};
    return std::make_unique<MeshSolid>(grid, Aabb{bounds.min - pad, bounds.max + pad},
                                       "mesh " + file.string() + " (" +
                                           std::to_string(meshInfo.triangles) + " triangles" +
                                           (meshInfo.closed() ? "" : ", open: shell") + ")",
                                       shellHalfThickness);
}

}  // namespace pbf
