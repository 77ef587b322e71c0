// `pbf run`: simulate a scene and write its outputs.
//
// Output directory layout:
//   frame_00000.ply ...  particles per frame (frame 0 is the initial state)
//   stats.csv            one row per frame (columns in docs/outputs.md)
//   summary.json         totals of the run
//   checkpoint.pbfck     the state to resume from (include/pbf/checkpoint.hpp)
// Every file is replaced atomically, so the directory is consistent at any
// moment a run is killed; `resume` continues from the checkpoint and writes
// frames bit-identical to an uninterrupted run (docs/reliability.md).
#pragma once

#include <cstddef>
#include <cstdint>
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

    // Continue from <outputDirectory>/checkpoint.pbfck instead of frame 0.
    bool resume = false;
    // A checkpoint is written when this many frames (0: never) or this many
    // wall-clock seconds (0: never) have passed since the last one, when the
    // run stops early, and at the end.
    int checkpointEvery = 10;
    double checkpointSeconds = 60.0;
    // Polled between frames; when it returns true the run writes a checkpoint
    // and returns with RunSummary::interrupted set. May be empty.
    std::function<bool()> stopRequested;
    // Free space the run leaves on the output disk: before each frame it
    // checks that the frame, its checkpoint and this reserve fit.
    std::uintmax_t reserveBytes = std::uintmax_t{16} << 20;
    // Notices for the user (resumed from ..., low disk space); may be empty.
    std::function<void(const std::string&)> onNotice;
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
    std::size_t maxInsideSolid = 0;    // over all frames; 0 in a correct run
    std::size_t skippedInSolids = 0;   // fluid-block sites left empty because a solid was there
    int resumedFromFrame = -1;         // frame of the checkpoint resumed from, -1 if none
    bool interrupted = false;          // stopRequested() ended the run early
    int lastFrame = 0;                 // last frame written
    std::filesystem::path checkpoint;  // last checkpoint written (empty if none)
};

// Runs the scene. Throws IoError if an output cannot be written (or, with
// `resume`, the checkpoint is missing, corrupt or from another scene) and
// StateError when the state guard stops the run; in that case the last good
// frame's state is saved as the checkpoint first and the message says so.
RunSummary runScene(const Scene& scene, const RunOptions& options);

// The stats.csv header line (without newline) and one row.
std::string statsCsvHeader();
std::string statsCsvRow(const FrameReport& report);

std::filesystem::path frameFileName(int frame);  // "frame_00042.ply"

}  // namespace pbf
