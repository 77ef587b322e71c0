#include "pbf/surface/mesh.hpp"

#include <algorithm>
#include <bit>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <numeric>
#include <ostream>
#include <string>
#include <unordered_map>

#include "pbf/io/io.hpp"
#include "pbf/io/vtk.hpp"

namespace pbf::surface {
namespace {

static_assert(std::endian::native == std::endian::little,
              "binary PLY output assumes a little-endian host");

Vec3 at(const TriangleMesh& m, std::uint32_t i) {
    return m.vertices[i];
}

}  // namespace

double meshVolume(const TriangleMesh& mesh) {
    // Sum of signed tetrahedra (origin, a, b, c): V = 1/6 sum a . (b x c).
    // Relative to the first vertex to keep float cancellation small.
    if (mesh.vertices.empty()) return 0.0;
    const Vec3 o = mesh.vertices[0];
    double sum = 0.0;
    for (const auto& t : mesh.triangles) {
        const Vec3 a = at(mesh, t[0]) - o, b = at(mesh, t[1]) - o, c = at(mesh, t[2]) - o;
        sum += double(a.x) * (double(b.y) * c.z - double(b.z) * c.y) -
               double(a.y) * (double(b.x) * c.z - double(b.z) * c.x) +
               double(a.z) * (double(b.x) * c.y - double(b.y) * c.x);
    }
    return sum / 6.0;
}

double meshArea(const TriangleMesh& mesh) {
    double sum = 0.0;
    for (const auto& t : mesh.triangles)
        sum +=
            0.5 *
            double(length(cross(at(mesh, t[1]) - at(mesh, t[0]), at(mesh, t[2]) - at(mesh, t[0]))));
    return sum;
}

EdgeReport checkEdges(const TriangleMesh& mesh) {
    // Per undirected edge: number of uses and the sum of directions
    // (+1 for a->b with a < b, -1 for b->a); a well-oriented closed mesh has
    // every edge used twice with directions summing to 0.
    struct Use {
        int count = 0;
        int direction = 0;
    };
    std::unordered_map<std::uint64_t, Use> edges;
    edges.reserve(mesh.triangles.size() * 2);
    for (const auto& t : mesh.triangles)
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t a = t[k], b = t[(k + 1) % 3];
            const std::uint64_t key = (std::uint64_t(std::min(a, b)) << 32) | std::max(a, b);
            Use& u = edges[key];
            ++u.count;
            u.direction += a < b ? 1 : -1;
        }
    EdgeReport report;
    report.edges = edges.size();
    for (const auto& [key, u] : edges) {
        if (u.count == 1)
            ++report.boundaryEdges;
        else if (u.count > 2)
            ++report.nonManifoldEdges;
        else if (u.direction != 0)
            ++report.misorientedEdges;
    }
    return report;
}

std::size_t countComponents(const TriangleMesh& mesh) {
    std::vector<std::uint32_t> parent(mesh.vertices.size());
    std::iota(parent.begin(), parent.end(), 0u);
    auto find = [&](std::uint32_t x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
    };
    std::vector<bool> used(mesh.vertices.size(), false);
    for (const auto& t : mesh.triangles) {
        for (std::uint32_t v : t) used[v] = true;
        parent[find(t[1])] = find(t[0]);
        parent[find(t[2])] = find(t[0]);
    }
    std::size_t components = 0;
    for (std::uint32_t v = 0; v < parent.size(); ++v)
        if (used[v] && find(v) == v) ++components;
    return components;
}

void writeMeshObj(const std::filesystem::path& path, const TriangleMesh& mesh) {
    writeFileAtomically(path, [&](std::ostream& out) {
        std::string buffer = "# water surface written by pbf\n";
        buffer.reserve(1 << 20);
        char line[96];
        auto flush = [&] {
            out.write(buffer.data(), static_cast<std::streamsize>(buffer.size()));
            buffer.clear();
        };
        auto vectors = [&](const char* tag, const std::vector<Vec3>& vs) {
            for (const Vec3& v : vs) {
                const int n = std::snprintf(line, sizeof line, "%s %.7g %.7g %.7g\n", tag,
                                            double(v.x), double(v.y), double(v.z));
                buffer.append(line, static_cast<std::size_t>(n));
                if (buffer.size() > (1u << 20) - 128) flush();
            }
        };
        vectors("v", mesh.vertices);
        vectors("vn", mesh.normals);
        const bool normals = !mesh.normals.empty();
        for (const auto& t : mesh.triangles) {
            const unsigned a = t[0] + 1, b = t[1] + 1, c = t[2] + 1;
            const int n = normals ? std::snprintf(line, sizeof line, "f %u//%u %u//%u %u//%u\n", a,
                                                  a, b, b, c, c)
                                  : std::snprintf(line, sizeof line, "f %u %u %u\n", a, b, c);
            buffer.append(line, static_cast<std::size_t>(n));
            if (buffer.size() > (1u << 20) - 128) flush();
        }
        flush();
    });
}

void writeMeshPly(const std::filesystem::path& path, const TriangleMesh& mesh) {
    const bool normals = !mesh.normals.empty();
    if (normals && mesh.normals.size() != mesh.vertices.size())
        throw IoError(path.string() + ": the mesh has " + std::to_string(mesh.normals.size()) +
                      " normals for " + std::to_string(mesh.vertices.size()) + " vertices");
    writeFileAtomically(path, [&](std::ostream& out) {
        out << "ply\nformat binary_little_endian 1.0\ncomment water surface written by pbf\n"
            << "element vertex " << mesh.vertices.size() << "\n"
            << "property float x\nproperty float y\nproperty float z\n"
            << (normals ? "property float nx\nproperty float ny\nproperty float nz\n" : "")
            << "element face " << mesh.triangles.size() << "\n"
            << "property list uchar uint vertex_indices\nend_header\n";
        static_assert(sizeof(Vec3) == 12);
        if (normals) {  // x y z nx ny nz per vertex
            std::vector<Vec3> interleaved;
            interleaved.reserve(2 * mesh.vertices.size());
            for (std::size_t k = 0; k < mesh.vertices.size(); ++k) {
                interleaved.push_back(mesh.vertices[k]);
                interleaved.push_back(mesh.normals[k]);
            }
            out.write(reinterpret_cast<const char*>(interleaved.data()),
                      static_cast<std::streamsize>(interleaved.size() * sizeof(Vec3)));
        } else {
            out.write(reinterpret_cast<const char*>(mesh.vertices.data()),
                      static_cast<std::streamsize>(mesh.vertices.size() * sizeof(Vec3)));
        }
        std::vector<char> faces(mesh.triangles.size() * 13);
        for (std::size_t k = 0; k < mesh.triangles.size(); ++k) {
            faces[13 * k] = 3;
            std::memcpy(&faces[13 * k + 1], mesh.triangles[k].data(), 12);
        }
        out.write(faces.data(), static_cast<std::streamsize>(faces.size()));
    });
}

TriangleMesh readMeshPly(const std::filesystem::path& path) {
    const auto fail = [&](const std::string& what) { throw IoError(path.string() + ": " + what); };
    std::ifstream in(path, std::ios::binary);
    if (!in) fail("cannot open");
    // The header writeMeshPly writes, line by line (comments skipped); the
    // normals' three lines are optional.
    const std::vector<std::string> expected = {"ply",
                                               "format binary_little_endian 1.0",
                                               "element vertex",
                                               "property float x",
                                               "property float y",
                                               "property float z",
                                               "property float nx",
                                               "property float ny",
                                               "property float nz",
                                               "element face",
                                               "property list uchar uint vertex_indices",
                                               "end_header"};
    std::size_t vertices = 0, faces = 0;
    bool normals = false;
    std::string line;
    for (std::size_t k = 0; k < expected.size();) {
        if (!std::getline(in, line)) fail("truncated PLY header");
        if (line.starts_with("comment")) continue;
        if (expected[k] == "property float nx" && line != expected[k]) {
            k += 3;  // no normals
            continue;
        }
        normals = normals || line == "property float nx";
        const bool count = expected[k].starts_with("element ");
        if (count ? !line.starts_with(expected[k] + " ") : line != expected[k])
            fail("not a surface PLY of pbf mesh (expected '" + expected[k] + "', got '" + line +
                 "')");
        if (count) (k == 2 ? vertices : faces) = std::stoul(line.substr(expected[k].size() + 1));
        ++k;
    }
    const std::size_t vertexBytes = normals ? 24 : 12;
    const auto headerEnd = in.tellg();
    in.seekg(0, std::ios::end);
    const auto bytes = static_cast<std::size_t>(in.tellg() - headerEnd);
    in.seekg(headerEnd);
    if (vertices > bytes / vertexBytes || faces > (bytes - vertices * vertexBytes) / 13)
        fail("file is shorter than its vertex and face counts say");
    TriangleMesh mesh;
    mesh.vertices.resize(vertices);
    if (normals) mesh.normals.resize(vertices);
    std::vector<Vec3> row(normals ? 2 : 1);
    for (std::size_t k = 0; k < vertices; ++k) {
        in.read(reinterpret_cast<char*>(row.data()), std::streamsize(vertexBytes));
        mesh.vertices[k] = row[0];
        if (normals) mesh.normals[k] = row[1];
    }
    std::vector<char> face(13 * faces);
    if (!in.read(face.data(), std::streamsize(face.size()))) fail("truncated face data");
    mesh.triangles.resize(faces);
    for (std::size_t k = 0; k < faces; ++k) {
        if (face[13 * k] != 3) fail("face " + std::to_string(k) + " is not a triangle");
        std::memcpy(mesh.triangles[k].data(), &face[13 * k + 1], 12);
        for (const std::uint32_t v : mesh.triangles[k])
            if (v >= vertices) fail("face " + std::to_string(k) + " has a vertex out of range");
    }
    return mesh;
}

void writeMeshVtp(const std::filesystem::path& path, const TriangleMesh& mesh, double time) {
    vtk::writeTrianglesVtp(path, mesh.vertices, mesh.normals, mesh.triangles, time);
}

}  // namespace pbf::surface
