// Runs a surface-meshing job with a progress bar and a one-line summary
// (shared by `pbf mesh` and `pbf run --mesh`).
#pragma once

#include <CLI/CLI.hpp>

#include "pbf/surface/mesh_frames.hpp"

namespace pbf::cli {

// Registers the mesh options (radius, voxel size, smoothing, ...) on `command`
// writing into `job`, `formats` ("ply,vdb") and `frames` ("0:100:2").
void addMeshOptions(CLI::App& command, surface::MeshJob& job, std::string& formats,
                    std::string& frames);
// Returns the exit code.
int runMeshJob(const surface::MeshJob& job, bool quiet);

}  // namespace pbf::cli
