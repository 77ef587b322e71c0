// `pbf run`: simulate a scene and write its outputs (also what `pbf render`
// and Python's pbf.run drive).
//
// Output directory layout:
//   frame_00000.ply ...  particles per frame (frame 0 is the initial state)
//   stats.csv            one row per frame, appended as the run goes
//   bodies.csv           with rigid bodies: one row per body per frame, appended likewise
//   summary.json         totals of the run (and the error that stopped it, if any)
//   checkpoint.pbfck     the state to resume from (include/pbf/io/checkpoint.hpp)
// Every file is replaced atomically (stats.csv grows by whole rows), so the
// directory is consistent at any moment a run is killed; `resume` continues
// from the checkpoint and writes frames bit-identical to an uninterrupted run
// (docs/reliability.md).
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "pbf/io/scene.hpp"
#include "pbf/run/plot.hpp"
#include "pbf/world/world.hpp"

namespace pbf {

// How runScene runs; what it writes comes from the scene's `output`.
struct RunOptions {
    WorldOptions world;  // the backend
    // Writes further per-frame files (e.g. OpenVDB points, images) after the
    // PLY frame and before onFrame; may be empty.
    std::function<void(int frame, const World& world)> writeFrame;
    // Called after every frame (progress display); may be empty.
    std::function<void(const FrameReport&)> onFrame;
    // Called once the world is built (solids loaded, blocks filled); may be empty.
    std::function<void(const World&)> onStart;

    // Continue from <output.directory>/checkpoint.pbfck instead of frame 0.
    bool resume = false;
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
    // Wall time of this session spent writing the per-frame outputs (frame
    // files, stats rows, extra per-frame files) and the checkpoints.
    double outputSeconds = 0.0;
    double checkpointSeconds = 0.0;
    long long substeps = 0;
    double particleStepsPerSecond = 0.0;
    double maxDensityError = 0.0;      // over all frames
    double averageDensityError = 0.0;  // mean over frames of the per-frame average
    std::size_t maxEscaped = 0;        // over all frames; 0 in a correct run
    std::size_t maxInsideSolid = 0;    // over all frames; 0 in a correct run
    std::size_t skippedInSolids = 0;   // fluid-block sites left empty because a solid was there
    std::uint64_t emitted = 0;         // particles the emitters added (the whole run)
    std::uint64_t removed = 0;         // particles the outlets removed (the whole run)
    int resumedFromFrame = -1;         // frame of the checkpoint resumed from, -1 if none
    bool interrupted = false;          // stopRequested() ended the run early
    int lastFrame = 0;                 // last frame written
    std::filesystem::path checkpoint;  // last checkpoint written (empty if none)
    // Why the run stopped early (the state guard, ...); its message says
    // which frames are good and where the run can be resumed from.
    std::optional<StepError> error;
};

// Runs the scene. Throws IoError if an output cannot be written (or, with
// `resume`, the checkpoint is missing, corrupt or from another scene) and
// SceneError for an invalid scene or a broken mesh. A frame that fails
// (the state guard) ends the run with RunSummary::error set.
RunSummary runScene(const Scene& scene, const RunOptions& options);

// The stats.csv header line (without newline) and one row.
std::string statsCsvHeader();
std::string statsCsvRow(const FrameReport& report);
// The bodies.csv header line (without newline) and the rows of the world's
// current frame, one per body, each ending in a newline.
std::string bodiesCsvHeader();
std::string bodiesCsvRows(const World& world);

std::filesystem::path frameFileName(int frame);  // "frame_00042.ply"

// stats.csv read back: every column of the header by name, one value per row.
struct StatsTable {
    std::vector<std::string> names;
    std::vector<std::vector<double>> columns;  // columns[k] holds the values of names[k]
    std::size_t rows() const { return columns.empty() ? 0 : columns.front().size(); }
    // The column called `name`; throws IoError naming the file when there is none.
    const std::vector<double>& column(const std::string& name) const;
    std::string file;  // for messages
};

// Reads a stats.csv; throws IoError naming the file (and line) when it is
// missing, empty or has a row that is not numbers.
StatsTable readStatsCsv(const std::filesystem::path& file);

// The statistics of a run against simulated time: density error (average and
// maximum), kinetic energy, particle count, substeps per frame, step time
// (and its stages) and maximum speed; `sceneName` goes in the title.
plot::Figure statsFigure(const StatsTable& stats, const std::string& sceneName);

// The frame a run's poster image shows: the frame with the most kinetic
// energy (the moment the most is happening: for a dam break, the surge
// running into the far wall). Only frames for which `eligible` is true
// count (those with an image); -1 when there is none.
int posterFrame(const StatsTable& stats, const std::function<bool(int frame)>& eligible);

// Plots RUN_DIR/stats.csv into RUN_DIR/stats.png (scene name from
// summary.json, else the directory's name); what `pbf plot` and the end of
// `pbf run` do. Throws IoError for a missing or broken stats.csv.
plot::Result plotRunStatistics(const std::filesystem::path& runDirectory,
                               const std::filesystem::path& png);

}  // namespace pbf
