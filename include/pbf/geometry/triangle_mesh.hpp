// Triangle meshes read from OBJ files and placed by a pbf::Transform: the
// surface of a "mesh" solid as triangles (the renderer draws it; the solver
// builds its distance field from the same file and transform, mesh_solid.cpp).
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <vector>

#include "pbf/core/vec3.hpp"
#include "pbf/geometry/solids.hpp"

namespace pbf {

struct TriangleMesh {
    std::vector<Vec3> vertices;                           // metres, transformed
    std::vector<std::array<std::uint32_t, 3>> triangles;  // indices into vertices
};

// Loads an OBJ (tinyobjloader, faces triangulated) and applies `transform`
// (Transform::apply, as the solver does) to every vertex. Degenerate
// triangles are dropped. Throws SolidError naming the file for: missing
// file, a format other than OBJ, a parse error, non-finite vertices, faces
// referring to missing vertices, or no triangles.
TriangleMesh loadTriangleMesh(const std::filesystem::path& file, const Transform& transform);

}  // namespace pbf
