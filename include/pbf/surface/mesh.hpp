// Triangle meshes of the water surface: the type, its measures (volume, area,
// open edges) and the files it is written to (binary PLY, OBJ, VTK .vtp).
//
// No OpenVDB types here: this header is cheap to include.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <vector>

#include "pbf/core/vec3.hpp"

namespace pbf::surface {

// An indexed triangle mesh; triangles are counter-clockwise seen from
// outside (normals point out of the water).
struct TriangleMesh {
    std::vector<Vec3> vertices;
    std::vector<std::array<std::uint32_t, 3>> triangles;
    // Unit vertex normals pointing out of the water, one per vertex, or
    // empty; the writers write them when present.
    std::vector<Vec3> normals;
};

// Enclosed volume (divergence theorem; positive for outward-facing triangles)
// and total area. Exact for closed meshes.
double meshVolume(const TriangleMesh& mesh);
double meshArea(const TriangleMesh& mesh);

struct EdgeReport {
    std::size_t edges = 0;             // distinct undirected edges
    std::size_t boundaryEdges = 0;     // used by one triangle (a hole)
    std::size_t nonManifoldEdges = 0;  // used by three or more triangles
    std::size_t misorientedEdges = 0;  // two triangles traverse it in the same direction
    bool watertight() const {
        return boundaryEdges == 0 && nonManifoldEdges == 0 && misorientedEdges == 0;
    }
};
EdgeReport checkEdges(const TriangleMesh& mesh);
// Number of connected pieces (triangles sharing a vertex are connected).
std::size_t countComponents(const TriangleMesh& mesh);

// Wavefront OBJ (text: "v x y z", "vn x y z", "f a//a b//b c//c", 1-based);
// every tool opens it.
void writeMeshObj(const std::filesystem::path& path, const TriangleMesh& mesh);
// Binary little-endian PLY (float x y z [nx ny nz]; face list uchar/uint):
// about half the OBJ's size, and faster to read.
void writeMeshPly(const std::filesystem::path& path, const TriangleMesh& mesh);
// Reads a file written by writeMeshPly (that layout, with or without
// normals). Throws IoError naming the file for anything else or a
// truncated file.
TriangleMesh readMeshPly(const std::filesystem::path& path);
// VTK XML PolyData for ParaView (pbf::vtk::writeTrianglesVtp, normals as
// the point array Normals); `time` in seconds.
void writeMeshVtp(const std::filesystem::path& path, const TriangleMesh& mesh, double time);

}  // namespace pbf::surface
