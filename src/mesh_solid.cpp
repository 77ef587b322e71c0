// Triangle-mesh solids: OBJ loading (tinyobjloader) and a narrow-band signed
// distance field built by OpenVDB (tools::meshToLevelSet; Bridson-style
// closest-triangle distances with inside/outside from a flood fill).
#include <openvdb/openvdb.h>
#include <openvdb/tools/Interpolation.h>
#include <openvdb/tools/MeshToVolume.h>
#include <tiny_obj_loader.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <mutex>
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
          voxel_(static_cast<float>(grid_->voxelSize()[0])),
          shellHalfThickness_(shellHalfThickness) {}

    float signedDistance(const Vec3& p, Vec3& normal) const override {
        const auto& tree = grid_->tree();
        const openvdb::math::Transform& xform = grid_->transform();
        auto sample = [&](float x, float y, float z) {
            return openvdb::tools::BoxSampler::sample(tree, xform.worldToIndex(openvdb::Vec3d(x, y, z)));
        };
        const float d = sample(p.x, p.y, p.z);
        // Central differences one voxel apart: the level set's gradient.
        const float e = voxel_;
        Vec3 g{sample(p.x + e, p.y, p.z) - sample(p.x - e, p.y, p.z),
               sample(p.x, p.y + e, p.z) - sample(p.x, p.y - e, p.z),
               sample(p.x, p.y, p.z + e) - sample(p.x, p.y, p.z - e)};
        if (shellHalfThickness_ > 0.0f) {
            // Unsigned field of an open mesh: a shell around the surface.
            if (d < shellHalfThickness_ && length(g) == 0.0f) g = {0.0f, 1.0f, 0.0f};
            const float len = length(g);
            normal = len > 0.0f ? g * (1.0f / len) : Vec3{0.0f, 1.0f, 0.0f};
            return d - shellHalfThickness_;
        }
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
    float voxel_;
    float shellHalfThickness_;
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
