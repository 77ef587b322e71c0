// `pbf run`: simulate a scene and write its outputs.
//
// Output directory layout:
//   frame_00000.ply ...  particles per frame (frame 0 is the initial state)
//   stats.csv            one row per frame (columns in docs/outputs.md)
//   summary.json         totals of the run
// Every file is replaced atomically, so the directory is consistent at any
// moment a run is killed.
#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <string>

#include "pbf/scene.hpp"
#include "pbf/simulation.hpp"

namespace pbf {

struct RunOptions {
    std::filesystem::path outputDirectory;  // created if missing
    int frames = 0;                         // frames after the initial one
    bool writeParticles = true;
    // Writes further per-frame files (e.g. OpenVDB points, which libpbf's
    // core does not link), before onFrame; may be empty.
    std::function<void(int frame, const ParticleStore& particles)> writeFrame;
    // Called after every frame (progress display); may be empty.
    std::function<void(const FrameReport&)> onFrame;
    // Called once the scene is built (solids loaded, blocks filled); may be empty.
    std::function<void(const Simulation&)> onStart;
};

struct RunSummary {
    int frames = 0;
    std::size_t particles = 0;
    double simulatedSeconds = 0.0;
    double wallSeconds = 0.0;
    long long substeps = 0;
    double particleStepsPerSecond = 0.0;
    double maxDensityError = 0.0;      // over all frames
    double averageDensityError = 0.0;  // mean over frames of the per-frame average
    std::size_t maxEscaped = 0;        // over all frames; 0 in a correct run
    std::size_t maxInsideSolid = 0;   // over all frames; 0 in a correct run
    std::size_t skippedInSolids = 0;  // fluid-block sites left empty because a solid was there
};

// Runs the scene; throws IoError if an output cannot be written.
RunSummary runScene(const Scene& scene, const RunOptions& options);

// The stats.csv header line (without newline) and one row.
std::string statsCsvHeader();
std::string statsCsvRow(const FrameReport& report);

std::filesystem::path frameFileName(int frame);  // "frame_00042.ply"

}  // namespace pbf
