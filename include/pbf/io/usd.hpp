// Universal Scene Description (USD) text layers (.usda) of a run: the stage
// that Maya (mayaUSD), Houdini (Solaris, File SOP), Omniverse, Blender,
// Unreal and usdview open whole (docs/clients.md).
//
// A stage is one small root layer plus one layer per frame for everything
// that is big and changes every frame (particles, surface meshes, white
// water), composed as USD value clips: the root names each frame's layer
// and the time it is active, so a reader opens only the frames it shows
// instead of parsing a whole run (a run of 1M particles is about 100 MB of
// text per frame). Small animated things (rigid bodies' transforms) are time
// samples in the root. Why value clips and text rather than one binary
// .usdc file is measured and explained in docs/clients.md.
//
// Floats are written with the fewest digits that read back to the same
// float (fmt's shortest round-trip form), so a reader gets the PLY frame's
// bits. There is no USD library in Debian: this is pbf's own writer, checked
// by an independent reader (tinyusdz) in the `clients` tests.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "pbf/core/vec3.hpp"
#include "pbf/geometry/pose.hpp"

namespace pbf::usd {

// One frame of a point set (particles or white water), in id order.
struct PointsFrame {
    std::span<const Vec3> positions;     // m
    std::span<const Vec3> velocities;    // m/s; empty or one per point
    std::span<const std::uint64_t> ids;  // empty or one per point
    std::span<const float> density;      // kg/m^3; empty or one per point
    std::span<const std::uint8_t> kind;  // white water's type; empty or one per point
    float width = 0.0f;                  // diameter of every point, m
};

// An indexed triangle mesh (normals: empty or one per vertex).
struct MeshData {
    std::span<const Vec3> vertices;
    std::span<const Vec3> normals;
    std::span<const std::array<std::uint32_t, 3>> triangles;
};

// A prim whose values come from one clip layer per frame.
struct ClipSeries {
    std::string name;         // prim name under /run: "particles", "surface", "whitewater"
    std::string type;         // "Points" or "Mesh"
    std::vector<int> frames;  // frames (time codes) with a layer, ascending
    std::string directory;    // the layers' folder, relative to the root layer
    std::vector<std::string> attributes;  // declarations for the manifest: "point3f[] points", ...
};

// The layer of `frame` in a series: "<directory>/<frame:05>.usda".
std::string clipLayerName(const ClipSeries& series, int frame);
// The attribute declarations that writePointsClip / writeMeshClip write.
std::vector<std::string> pointsAttributes(bool velocities, bool ids, bool density, bool kind);
std::vector<std::string> meshAttributes(bool normals);

// Writes one frame's layer of a Points prim named `name` (time code `frame`).
// Atomic; throws IoError naming the file.
void writePointsClip(const std::filesystem::path& path, const std::string& name, int frame,
                     const PointsFrame& points);
// Writes one frame's layer of a Mesh prim named `name`. Atomic; throws IoError.
void writeMeshClip(const std::filesystem::path& path, const std::string& name, int frame,
                   const MeshData& mesh);
// Writes a series' manifest (the attributes its clips hold), which spares a
// reader from opening every clip to find them: "<directory>/manifest.usda".
void writeClipManifest(const std::filesystem::path& rootDirectory, const ClipSeries& series);

// A static triangle mesh (a solid, or a rigid body's shape in its own frame).
struct StaticMesh {
    std::string name;
    Pose pose;  // of the mesh within its parent (identity for solids)
    std::vector<Vec3> vertices;
    std::vector<Vec3> normals;  // one per vertex, or empty
    std::vector<std::array<std::uint32_t, 3>> triangles;
};

// A rigid body: its frame (centre of mass, principal axes) at each frame
// from bodies.csv, and its shape in that frame when known.
struct BodyTrack {
    std::string name;
    std::vector<int> frames;
    std::vector<std::array<double, 3>> position;     // m
    std::vector<std::array<double, 4>> orientation;  // unit quaternion w, x, y, z
    std::optional<StaticMesh> shape;
};

struct Camera {
    Vec3 position, target;
    float fovY = 40.0f;   // degrees
    float aspect = 1.0f;  // width / height
};

// The root layer: time metadata, /run with the clip series, solids,
// bodies and camera.
struct Stage {
    std::string doc;
    double fps = 30.0;
    int startFrame = 0;
    int endFrame = 0;
    std::vector<ClipSeries> series;
    std::vector<StaticMesh> solids;
    std::vector<BodyTrack> bodies;
    std::optional<Camera> camera;
};

// Writes the root layer. Atomic; throws IoError naming the file.
void writeRootLayer(const std::filesystem::path& path, const Stage& stage);

}  // namespace pbf::usd
