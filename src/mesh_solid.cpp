// Triangle-mesh solids: OBJ loading (tinyobjloader) and a narrow-band signed
// distance field built by OpenVDB (tools::meshToLevelSet; Bridson-style
// closest-triangle distances with inside/outside from a flood fill).
#include <openvdb/openvdb.h>
#include <openvdb/tools/MeshToVolume.h>
#include <tiny_obj_loader.h>

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <cmath>
#include <map>
#include <mutex>
#include <optional>
#include <utility>

#include "pbf/solids.hpp"

namespace pbf {
namespace {

constexpr std::size_t kMaxTriangles = 10'000'000;

[[noreturn]] void fail(const std::filesystem::path& file, const std::string& message) {
    throw SolidError(file.string() + ": " + message);
}

class MeshSolid final : public Solid {
public:
    MeshSolid(openvdb::FloatGrid::Ptr grid, Aabb bounds, std::string description, float shellHalfThickness)
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
        const openvdb::Coord base(static_cast<int>(std::floor(index.x())), static_cast<int>(std::floor(index.y())),
                                  static_cast<int>(std::floor(index.z())));
        const float fx = static_cast<float>(index.x() - base.x());
        const float fy = static_cast<float>(index.y() - base.y());
        const float fz = static_cast<float>(index.z() - base.z());
        float v[2][2][2];
        for (int a = 0; a < 2; ++a)
            for (int b = 0; b < 2; ++b)
                for (int c = 0; c < 2; ++c) v[a][b][c] = accessor->getValue(base.offsetBy(a, b, c));
        auto lerp = [](float x0, float x1, float t) { return x0 + t * (x1 - x0); };
        // Interpolate along z, then y, then x, keeping the partial derivatives.
        float vz[2][2], dz[2][2];
        for (int a = 0; a < 2; ++a)
            for (int b = 0; b < 2; ++b) {
                vz[a][b] = lerp(v[a][b][0], v[a][b][1], fz);
                dz[a][b] = v[a][b][1] - v[a][b][0];
            }
        const float vy0 = lerp(vz[0][0], vz[0][1], fy), vy1 = lerp(vz[1][0], vz[1][1], fy);
        const float dy0 = vz[0][1] - vz[0][0], dy1 = vz[1][1] - vz[1][0];
        const float dz0 = lerp(dz[0][0], dz[0][1], fy), dz1 = lerp(dz[1][0], dz[1][1], fy);
        float d = lerp(vy0, vy1, fx);
        Vec3 g{vy1 - vy0, lerp(dy0, dy1, fx), lerp(dz0, dz1, fx)};
        if (shellHalfThickness_ > 0.0f) d -= shellHalfThickness_;  // open mesh: a shell
        const float len = length(g);
        normal = len > 0.0f ? g * (1.0f / len) : Vec3{0.0f, 1.0f, 0.0f};
        return d;
    }
    Aabb bounds() const override { return bounds_; }
    std::string describe() const override { return description_; }

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
                                     const MeshSolidOptions& options, MeshInfo* info, double maxVoxels) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(file, ec)) fail(file, "cannot open mesh file (no such file)");
    if (file.extension() != ".obj" && file.extension() != ".OBJ")
        fail(file, "unsupported mesh format '" + file.extension().string() + "' (OBJ is supported)");
    if (!(options.voxelSize > 0.0f) || !(options.bandWidth > 0.0f)) fail(file, "invalid voxel size or band");

    tinyobj::ObjReaderConfig config;
    config.triangulate = true;
    config.vertex_color = false;
    tinyobj::ObjReader reader;
    if (!reader.ParseFromFile(file.string(), config)) fail(file, "cannot read OBJ: " + reader.Error());
    const tinyobj::attrib_t& attrib = reader.GetAttrib();

    std::vector<openvdb::Vec3s> points;
    points.reserve(attrib.vertices.size() / 3);
    Aabb bounds{{1e30f, 1e30f, 1e30f}, {-1e30f, -1e30f, -1e30f}};
    for (std::size_t v = 0; v + 2 < attrib.vertices.size(); v += 3) {
        const Vec3 raw{attrib.vertices[v], attrib.vertices[v + 1], attrib.vertices[v + 2]};
        if (!std::isfinite(raw.x) || !std::isfinite(raw.y) || !std::isfinite(raw.z))
            fail(file, "vertex " + std::to_string(v / 3 + 1) + " is not finite");
        const Vec3 p = transform.apply(raw);
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
            fail(file, "vertex " + std::to_string(v / 3 + 1) + " is not finite after the transform");
        points.emplace_back(p.x, p.y, p.z);
        bounds.min = {std::min(bounds.min.x, p.x), std::min(bounds.min.y, p.y), std::min(bounds.min.z, p.z)};
        bounds.max = {std::max(bounds.max.x, p.x), std::max(bounds.max.y, p.y), std::max(bounds.max.z, p.z)};
    }

    std::vector<openvdb::Vec3I> triangles;
    double area = 0.0;
    std::map<std::pair<unsigned, unsigned>, unsigned> edgeUse;
    for (const tinyobj::shape_t& shape : reader.GetShapes()) {
        const auto& indices = shape.mesh.indices;
        if (indices.size() / 3 + triangles.size() > kMaxTriangles)
            fail(file, "more than " + std::to_string(kMaxTriangles) + " triangles; decimate the mesh first");
        for (std::size_t k = 0; k + 2 < indices.size(); k += 3) {
            unsigned t[3];
            for (int c = 0; c < 3; ++c) {
                const int index = indices[k + c].vertex_index;
                if (index < 0 || std::size_t(index) >= points.size())
                    fail(file, "face " + std::to_string(triangles.size() + 1) + " refers to a missing vertex");
                t[c] = static_cast<unsigned>(index);
            }
            if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) continue;  // degenerate
            triangles.emplace_back(t[0], t[1], t[2]);
            for (int c = 0; c < 3; ++c) ++edgeUse[std::minmax(t[c], t[(c + 1) % 3])];
            const openvdb::Vec3s a = points[t[1]] - points[t[0]], b = points[t[2]] - points[t[0]];
            area += 0.5 * double(a.cross(b).length());
        }
    }
    if (triangles.empty()) fail(file, "the mesh has no triangles");

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
        fail(file, "the distance field would need about " + std::to_string(static_cast<long long>(estimatedVoxels)) +
                       " voxels at voxel size " + std::to_string(voxel) +
                       " m; scale the mesh down or use larger particles");

    static std::once_flag initialised;
    std::call_once(initialised, [] { openvdb::initialize(); });
    const openvdb::math::Transform::Ptr xform = openvdb::math::Transform::createLinearTransform(voxel);
    openvdb::FloatGrid::Ptr grid;
    float shellHalfThickness = 0.0f;
    if (meshInfo.closed()) {
        grid = openvdb::tools::meshToLevelSet<openvdb::FloatGrid>(*xform, points, triangles, halfWidth);
    } else {
        // No inside to flood-fill: use the unsigned distance and a shell.
        std::vector<openvdb::Vec4I> quads;
        grid = openvdb::tools::meshToUnsignedDistanceField<openvdb::FloatGrid>(*xform, points, triangles,
                                                                                 quads, halfWidth);
        shellHalfThickness = std::max(0.5f * options.shellThickness, 0.5f * voxel);
    }
    const Vec3 pad{options.bandWidth, options.bandWidth, options.bandWidth};
    return std::make_unique<MeshSolid>(grid, Aabb{bounds.min - pad, bounds.max + pad},
                                       "mesh " + file.string() + " (" + std::to_string(meshInfo.triangles) +
                                           " triangles" + (meshInfo.closed() ? "" : ", open: shell") + ")",
                                       shellHalfThickness);
}

}  // namespace pbf
