// `pbf export usd`: a run directory as one USD stage (shared by `pbf export`
// and `pbf run --usd`).
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>

#include "pbf/io/scene.hpp"

namespace pbf::cli {

struct UsdExport {
    int frames = 0;         // particle frames
    int surfaceFrames = 0;  // frames with a surface mesh
    int foamFrames = 0;     // frames with white water
    int bodies = 0;
    int solids = 0;
    std::uintmax_t bytes = 0;  // the root layer and the per-frame layers
    double seconds = 0.0;
    std::filesystem::path root;
};

// Writes the stage of the run in `run` to `rootFile` (a .usda) and its
// per-frame layers to <rootFile's stem>_usd/ beside it. Throws IoError
// naming the file for a directory that is not a run, a missing or broken
// frame; nothing is left half-written. `warn` hears about parts left out.
// The solids, bodies' shapes and camera come from `scene`, else from the
// scene file that summary.json names.
UsdExport exportRunUsd(const std::filesystem::path& run, const std::filesystem::path& rootFile,
                       bool quiet, const std::function<void(const std::string&)>& warn,
                       const Scene* scene = nullptr);
// "121 particle frames, ...: 12.3 MB in 1.2 s -> out/x/run.usda"
std::string describe(const UsdExport& e);

}  // namespace pbf::cli
