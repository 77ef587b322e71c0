// Scene files: JSON documents that describe a whole simulation.
//
// The format (every field, unit, default and range) is documented in
// docs/scenes.md. Loading is strict: unknown keys, wrong types, out-of-range
// values, empty or overlapping fluid blocks are errors that name the file and
// the field, e.g. "scenes/x.json: solver.iterations: must be in [1, 100], got 0".
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "pbf/core/params.hpp"
#include "pbf/world/world_def.hpp"

namespace pbf {

// Images of every frame while the run simulates (`pbf run --render`; drawn
// by the CLI through pbf_render, libpbf has no GL): PNG frames, a video and a
// poster image. Plain values here; docs/scenes.md has the ranges.
struct RenderOutput {
    std::string style;            // "" (none), "spheres" or "liquid"
    std::string color = "speed";  // spheres: "speed", "density" or "flat"
    int width = 960;              // pixels, [16, 8192]
    int height = 540;             // pixels, [16, 8192]
    // Camera in metres; unset: the view of the README images, framing the domain.
    std::optional<Vec3> cameraPosition;
    std::optional<Vec3> cameraTarget;
    float fov = 40.0f;  // vertical field of view, degrees, [1, 170]
    bool enabled() const { return !style.empty(); }
};

// What `pbf run` writes (the frame rate is the definition's fps).
struct OutputParams {
    int frames = 90;              // frames to simulate, [1, 1e6]
    std::string directory;        // default "out/<scene name>"
    bool writeParticles = true;   // binary PLY per frame
    bool writeVdbPoints = false;  // OpenVDB points per frame (frame_NNNNN.vdb, pbf_surface)
    // VTK XML particles per frame (frame_NNNNN.vtu) and particles.pvd with
    // the frame times, for ParaView (include/pbf/io/vtk.hpp).
    bool writeVtk = false;
    // H5Part particles per frame (frame_NNNNN.h5part) and particles.h5part
    // listing them with their times, for ParaView; written by all ranks of a
    // distributed run at once (include/pbf/io/h5part.hpp; needs PBF_HDF5).
    bool writeH5Part = false;
    // A USD stage of the run (run.usda and its per-frame layers in
    // run_usd/, docs/clients.md), written by `pbf run` at the end of the
    // run, after the surfaces of --mesh; as `pbf export usd RUN_DIR`.
    bool writeUsd = false;
    // Checkpoints for --resume (docs/reliability.md): one is written when
    // `checkpointEvery` frames or `checkpointSeconds` of wall time have passed
    // since the last one (0 turns that trigger off), and at the end of a run.
    int checkpointEvery = 10;         // frames, [0, 1e6]
    float checkpointSeconds = 60.0f;  // wall-clock seconds, [0, 1e6]
    bool writeCheckpoints = true;     // false: none at all (not even at the end)
    RenderOutput render;
};

// A command-line override "path=value": path is dot-separated
// ("solver.iterations"), value is JSON ("8", "[0,-9.81,0]") or a bare string.
struct SceneOverride {
    std::string path;
    std::string value;
};

// A scene file: a world definition (name from the file name unless given,
// source = the file) plus what `pbf run` writes.
struct Scene : WorldDef {
    OutputParams output;
    // Hash of the scene document after overrides, without the output fields
    // that do not change the simulated states (frames, directory, particles,
    // checkpoint and speed-limit settings): a checkpoint records it so that a
    // run is only resumed with the scene it was started with.
    std::uint64_t fingerprint = 0;
    // The overrides applied to the file, in order (summary.json records
    // them, so that `pbf export usd` can load the scene the run ran).
    std::vector<SceneOverride> overrides;
};

SceneOverride parseOverride(std::string_view assignment);  // throws SceneError

Scene loadScene(const std::filesystem::path& file,
                const std::vector<SceneOverride>& overrides = {});
Scene parseScene(std::string_view jsonText, const std::string& sourceName,
                 const std::vector<SceneOverride>& overrides = {});

}  // namespace pbf
