#include "run/run_driver.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <nlohmann/json.hpp>
#include <system_error>

#include "pbf/io.hpp"
#include "pbf/state_guard.hpp"
#include "pbf/version.hpp"

namespace pbf::detail {
namespace {

void writeSummary(const std::filesystem::path& file, const Scene& scene, const RunSummary& s) {
    nlohmann::json j;
    j["pbf_version"] = kVersion;
    j["scene"] = scene.name;
    j["scene_file"] = scene.source;
    j["frames"] = s.frames;
    j["particles"] = s.particles;
    j["simulated_seconds"] = s.simulatedSeconds;
    j["wall_seconds"] = s.wallSeconds;
    j["substeps"] = s.substeps;
    j["particle_steps_per_second"] = s.particleStepsPerSecond;
    j["max_density_error"] = s.maxDensityError;
    j["average_density_error"] = s.averageDensityError;
    j["particle_radius"] = scene.simulation.particleRadius;  // read by `pbf mesh`
    j["max_escaped"] = s.maxEscaped;
    j["max_inside_solid"] = s.maxInsideSolid;
    j["skipped_in_solids"] = s.skippedInSolids;
    j["resumed_from_frame"] = s.resumedFromFrame;
    j["interrupted"] = s.interrupted;
    writeFileAtomically(file, [&](std::ostream& out) {
        out << j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) << "\n";
    });
}

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

constexpr double kMiB = 1024.0 * 1024.0;

// Bytes of one PLY frame (header and 32 bytes per particle).
std::uintmax_t plyBytes(std::size_t particles) {
    return 512 + std::uintmax_t{particles} * 32;
}

}  // namespace

void RunDriver::createDirectory() const {
    std::error_code ec;
    fs::create_directories(dir_, ec);
    if (ec || !fs::is_directory(dir_))
        throw IoError(dir_.string() + ": cannot create output directory" +
                      (ec ? " (" + ec.message() + ")" : ""));
}

// A run killed while writing leaves the temporary file of writeFileAtomically
// (".frame_00012.ply.tmp123456"); the file it was to replace is whole.
void RunDriver::removeStaleTemporaries() const {
    std::error_code ec;
    for (const fs::directory_entry& entry : fs::directory_iterator(dir_, ec)) {
        const std::string name = entry.path().filename().string();
        if (name.size() > 1 && name[0] == '.' && name.find(".tmp") != std::string::npos &&
            entry.is_regular_file(ec))
            fs::remove(entry.path(), ec);
    }
}

void RunDriver::resumeFromCheckpoint() {
    const fs::path file = dir_ / kCheckpointFileName;
    std::error_code ec;
    if (!fs::exists(file, ec))
        throw IoError(file.string() +
                      ": no checkpoint to resume from; run without --resume to start at frame 0");
    removeStaleTemporaries();
    Checkpoint checkpoint = readCheckpoint(file);
    restoreCheckpoint(checkpoint, simulation_, file.string());
    totals_ = std::move(checkpoint.totals);
    previousWallSeconds_ = totals_.wallSeconds;
    summary_.resumedFromFrame = simulation_.frame();
    lastCheckpointFrame_ = simulation_.frame();
    summary_.checkpoint = file;
    // stats.csv may hold rows of frames computed after the checkpoint by the
    // killed run: put it back to the checkpoint's rows; they are recomputed.
    writeFileAtomically(dir_ / "stats.csv", [&](std::ostream& out) { out << totals_.statsCsv; });
    notice(simulation_.frame() >= options_.frames
               ? fmt::format("{} is at frame {}: nothing left to simulate up to frame {}",
                             file.string(), simulation_.frame(), options_.frames)
               : fmt::format("resuming from frame {} of {} ({})", simulation_.frame(),
                             options_.frames, file.string()));
}

void RunDriver::warnIfDiskTooSmall() const {
    std::error_code ec;
    const fs::space_info space = fs::space(dir_, ec);
    const int remaining = options_.frames - simulation_.frame();
    if (ec || remaining <= 0) return;
    const std::size_t n = simulation_.particles().size();
    const double needed = double(options_.writeParticles ? plyBytes(n) : 0) * remaining +
                          double(checkpointBytes(n, totals_.statsCsv.size()));
    if (double(space.available) < needed)
        notice(fmt::format(
            "{}: the {} remaining frames need about {:.0f} MiB but only {:.0f} MiB are free; the "
            "run will stop when the disk is full (continue it with --resume after freeing space)",
            dir_.string(), remaining, needed / kMiB, double(space.available) / kMiB));
}

// Refuses to start a frame whose files would not fit: a full disk is
// reported before any file is cut short (writeFileAtomically would also
// report it, but a near-full disk hurts everything else on the machine).
void RunDriver::checkFreeSpace() const {
    std::error_code ec;
    const fs::space_info space = fs::space(dir_, ec);
    if (ec) return;  // unknown (some network file systems): the writes report failures
    const std::size_t n = simulation_.particles().size();
    const std::uintmax_t frame =
        (options_.writeParticles ? plyBytes(n) : 0) + totals_.statsCsv.size() + 256;
    const std::uintmax_t needed = frame + checkpointBytes(n, totals_.statsCsv.size());
    if (space.available < needed + options_.reserveBytes)
        throw IoError(
            fmt::format("{}: output disk full: {:.1f} MiB free, but the next frame and its "
                        "checkpoint need {:.1f} MiB and "
                        "{:.1f} MiB are kept in reserve; free space or choose another --out, then "
                        "continue with --resume",
                        dir_.string(), double(space.available) / kMiB, double(needed) / kMiB,
                        double(options_.reserveBytes) / kMiB));
}

void RunDriver::record(const FrameReport& report) {
    checkFreeSpace();
    if (options_.writeParticles)
        writeParticlesPly(dir_ / frameFileName(report.frame), simulation_.particles());
    if (options_.writeFrame) options_.writeFrame(report.frame, simulation_.particles());
    totals_.statsCsv += statsCsvRow(report) + "\n";
    writeFileAtomically(dir_ / "stats.csv", [&](std::ostream& out) { out << totals_.statsCsv; });
    totals_.maxDensityError = std::max(totals_.maxDensityError, report.state.maxDensityError);
    totals_.maxEscaped = std::max<std::uint64_t>(totals_.maxEscaped, report.state.escaped);
    totals_.maxInsideSolid =
        std::max<std::uint64_t>(totals_.maxInsideSolid, report.state.insideSolid);
    totals_.densityErrorSum += report.state.averageDensityError;
    totals_.substeps += report.substeps;
    totals_.solverMilliseconds += report.stageMs.total;
    if (options_.onFrame) options_.onFrame(report);

    // Keep this frame's state: it is what a checkpoint saves, now or when a
    // later step goes bad. The CSV only grows, so its length marks the rows.
    lastGood_ = captureCheckpoint(simulation_);
    lastGoodCsvBytes_ = totals_.statsCsv.size();
    RunTotals totals = totals_;
    totals.statsCsv.clear();
    lastGood_.totals = std::move(totals);
}

void RunDriver::saveLastGood() {
    lastGood_.totals.statsCsv = totals_.statsCsv.substr(0, lastGoodCsvBytes_);
    lastGood_.totals.wallSeconds = wallSeconds();
    const fs::path file = dir_ / kCheckpointFileName;
    writeCheckpoint(file, lastGood_);
    lastGood_.totals.statsCsv.clear();
    summary_.checkpoint = file;
    lastCheckpointFrame_ = lastGood_.frame;
    lastCheckpointTime_ = Clock::now();
}

bool RunDriver::checkpointDue() const {
    const int frames = simulation_.frame() - lastCheckpointFrame_;
    const double seconds =
        std::chrono::duration<double>(Clock::now() - lastCheckpointTime_).count();
    return (options_.checkpointEvery > 0 && frames >= options_.checkpointEvery) ||
           (options_.checkpointSeconds > 0.0 && seconds >= options_.checkpointSeconds);
}

void RunDriver::advance() {
    FrameReport report;
    try {
        report = simulation_.advanceFrame();
    } catch (const StateError& e) {
        saveLastGood();
        throw StateError(
            fmt::format("{}; the run stopped: frames up to {} are good and their state is saved "
                        "in {} (raise output.max_speed or change the scene to go on)",
                        e.what(), lastGood_.frame, summary_.checkpoint.string()),
            e.frame, e.substep, e.stage, e.particle);
    }
    record(report);
}

RunSummary RunDriver::run() {
    createDirectory();
    summary_.skippedInSolids = simulation_.skippedParticles();
    if (options_.onStart) options_.onStart(simulation_);
    if (options_.resume) {
        resumeFromCheckpoint();
        lastGood_ = captureCheckpoint(simulation_);
        lastGoodCsvBytes_ = totals_.statsCsv.size();
        RunTotals totals = totals_;
        totals.statsCsv.clear();
        lastGood_.totals = std::move(totals);
    } else {
        totals_.statsCsv = statsCsvHeader() + "\n";
        record(simulation_.report());
        lastCheckpointFrame_ = 0;  // frame 0 is recreated from the scene; no checkpoint needed
    }
    warnIfDiskTooSmall();
    while (simulation_.frame() < options_.frames) {
        if (options_.stopRequested && options_.stopRequested()) {
            summary_.interrupted = true;
            break;
        }
        advance();
        if (checkpointDue()) saveLastGood();
    }
    if (lastCheckpointFrame_ != simulation_.frame() || summary_.checkpoint.empty()) saveLastGood();

    RunSummary& s = summary_;
    s.frames = simulation_.frame();
    s.lastFrame = simulation_.frame();
    s.particles = simulation_.particles().size();
    s.simulatedSeconds = simulation_.time();
    s.wallSeconds = wallSeconds();
    s.substeps = totals_.substeps;
    s.maxDensityError = totals_.maxDensityError;
    s.maxEscaped = static_cast<std::size_t>(totals_.maxEscaped);
    s.maxInsideSolid = static_cast<std::size_t>(totals_.maxInsideSolid);
    s.averageDensityError = totals_.densityErrorSum / (simulation_.frame() + 1);
    s.particleStepsPerSecond =
        totals_.solverMilliseconds > 0.0
            ? double(s.particles) * double(s.substeps) / (totals_.solverMilliseconds * 1e-3)
            : 0.0;
    writeSummary(dir_ / "summary.json", scene_, s);
    return s;
}

}  // namespace pbf::detail
