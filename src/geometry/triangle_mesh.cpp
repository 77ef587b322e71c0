// OBJ surfaces as triangle lists (tinyobjloader), placed by Transform::apply.
#include "pbf/geometry/triangle_mesh.hpp"

#include <tiny_obj_loader.h>

#include <cmath>
#include <string>

namespace pbf {
namespace {

[[noreturn]] void fail(const std::filesystem::path& file, const std::string& message) {
    throw SolidError(file.string() + ": " + message);
}

bool finite(const Vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

}  // namespace

TriangleMesh loadTriangleMesh(const std::filesystem::path& file, const Transform& transform) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(file, ec))
        fail(file, "cannot open mesh file (no such file)");
    if (file.extension() != ".obj" && file.extension() != ".OBJ")
        fail(file,
             "unsupported mesh format '" + file.extension().string() + "' (OBJ is supported)");
    tinyobj::ObjReaderConfig config;
    config.triangulate = true;
    config.vertex_color = false;
    tinyobj::ObjReader reader;
    if (!reader.ParseFromFile(file.string(), config))
        fail(file, "cannot read OBJ: " + reader.Error());
    const tinyobj::attrib_t& attrib = reader.GetAttrib();

    TriangleMesh mesh;
    mesh.vertices.reserve(attrib.vertices.size() / 3);
    for (std::size_t v = 0; v + 2 < attrib.vertices.size(); v += 3) {
        const Vec3 raw{attrib.vertices[v], attrib.vertices[v + 1], attrib.vertices[v + 2]};
        if (!finite(raw)) fail(file, "vertex " + std::to_string(v / 3 + 1) + " is not finite");
        const Vec3 p = transform.apply(raw);
        if (!finite(p))
            fail(file,
                 "vertex " + std::to_string(v / 3 + 1) + " is not finite after the transform");
        mesh.vertices.push_back(p);
    }
    for (const tinyobj::shape_t& shape : reader.GetShapes()) {
        const auto& indices = shape.mesh.indices;
        for (std::size_t k = 0; k + 2 < indices.size(); k += 3) {
            std::array<std::uint32_t, 3> t{};
            for (std::size_t c = 0; c < 3; ++c) {
                const int index = indices[k + c].vertex_index;
                if (index < 0 || std::size_t(index) >= mesh.vertices.size())
                    fail(file, "face " + std::to_string(mesh.triangles.size() + 1) +
                                   " refers to a missing vertex");
                t[c] = static_cast<std::uint32_t>(index);
            }
            if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) continue;  // degenerate
            mesh.triangles.push_back(t);
        }
    }
    if (mesh.triangles.empty()) fail(file, "the mesh has no triangles");
    return mesh;
}

}  // namespace pbf
