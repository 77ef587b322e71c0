// `pbf mesh`'s pipeline: a directory of particle frames (frame_NNNNN.ply
// written by `pbf run`) -> one surface mesh (PLY / OBJ / VTK .vtp, the .vtp
// files listed in surface.pvd with their times) and level set (.vdb) per
// frame. Options and defaults in docs/surfaces.md.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "pbf/surface/surface.hpp"

namespace pbf::surface {

// Frames first, first + step, ... below end (Python slice "first:end:step";
// end < 0 means "to the last frame"). Parsed from "A", "A:B" or "A:B:S",
// each part optional ("::2", "10:"). Throws std::invalid_argument.
struct FrameRange {
    int first = 0;
    int end = -1;
    int step = 1;
    bool contains(int frame) const {
        return frame >= first && (end < 0 || frame < end) && (frame - first) % step == 0;
    }
};
FrameRange parseFrameRange(std::string_view text);

struct FrameFile {
    int frame = 0;
    std::filesystem::path path;
};
// The frame_NNNNN.ply files of `directory` inside `range`, in frame order.
// Throws IoError naming the directory if it is missing or has no such frame.
std::vector<FrameFile> listParticleFrames(const std::filesystem::path& directory,
                                          const FrameRange& range);

// The "<prefix>NNNNN<suffix>" files of `directory` (NNNNN at least five
// digits), in frame order; none when the directory is missing. Throws
// IoError if it cannot be listed.
std::vector<FrameFile> listFrameFiles(const std::filesystem::path& directory,
                                      std::string_view prefix, std::string_view suffix);

// "particle_radius" from `directory`/summary.json (written by `pbf run`),
// or 0 if the file or the field is absent. Throws IoError if it is malformed.
float radiusFromSummary(const std::filesystem::path& directory);
// "fps" from `directory`/summary.json likewise (0 if absent).
float fpsFromSummary(const std::filesystem::path& directory);

struct MeshFormats {
    bool ply = true;  // binary, with normals: the default mesh
    bool obj = false;
    bool vtk = false;  // .vtp + surface.pvd for ParaView
    bool vdb = true;   // the level set
};
// "ply,obj,vtk,vdb" (any non-empty subset). Throws std::invalid_argument.
MeshFormats parseMeshFormats(std::string_view text);

struct FrameMeshReport {
    int frame = 0;
    int index = 0;  // 0-based position in the job
    std::size_t particles = 0;
    std::size_t sprayDropped = 0;
    std::size_t vertices = 0;
    std::size_t triangles = 0;
    std::uintmax_t bytesWritten = 0;
    double seconds = 0.0;  // reading excluded: level set + mesh + writing
};

struct MeshJob {
    std::filesystem::path input;   // directory of frame_NNNNN.ply
    std::filesystem::path output;  // default: input / "surface"
    FrameRange range;
    // params.particleRadius <= 0: taken from summary.json, else estimated
    // from the first frame (estimateParticleRadius).
    SurfaceParams params;
    MeshFormats formats;
    // Frames per simulated second, for the times in surface.pvd (frame k at
    // k / fps); <= 0: from summary.json. Needed only for the vtk format.
    float fps = 0.0f;
    std::function<void(const FrameMeshReport&)> onFrame;  // may be empty
    int threads = 0;                                      // TBB worker threads, 0 = all cores
};

struct MeshSummary {
    int frames = 0;
    float particleRadius = 0.0f;
    std::string radiusSource;   // "option", "summary.json" or "estimated"
    std::size_t particles = 0;  // summed over frames
    std::size_t triangles = 0;  // summed over frames
    std::uintmax_t bytesWritten = 0;
    double seconds = 0.0;      // wall time
    double meshSeconds = 0.0;  // level set + mesh + write, summed
};

// Frames are processed one after another; each uses all cores through
// OpenVDB's TBB loops. Throws IoError / std::invalid_argument.
MeshSummary meshFrames(const MeshJob& job);

// Output names: surface_00042.ply / .obj / .vtp, levelset_00042.vdb; the
// collection of the .vtp files is surface.pvd.
std::filesystem::path surfaceFileName(int frame, std::string_view extension);
std::filesystem::path levelSetFileName(int frame);

}  // namespace pbf::surface
