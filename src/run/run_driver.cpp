#include "run/run_driver.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <system_error>

#include "pbf/core/distributed.hpp"
#include "pbf/core/state_guard.hpp"
#include "pbf/core/version.hpp"
#include "pbf/io/h5part.hpp"
#include "pbf/io/io.hpp"
#include "pbf/io/vtk.hpp"

namespace pbf::detail {
namespace {

nlohmann::json vec3(const Vec3& v) {
    return nlohmann::json::array({v.x, v.y, v.z});
}

// The rigid bodies at the end of the run: what each is and its last state.
nlohmann::json bodiesJson(const World& world) {
    nlohmann::json bodies = nlohmann::json::array();
    for (std::size_t k = 0; k < world.bodyCount(); ++k) {
        const RigidBodyInfo& info = world.bodyInfos()[k];
        const RigidBodyState& b = world.bodyStates()[k];
        const Quat& q = b.orientation;
        bodies.push_back({{"body", k},
                          {"field", info.field},
                          {"shape", info.describe},
                          {"mass", info.mass},
                          {"volume", info.volume},
                          {"position", vec3(b.position)},
                          {"orientation", nlohmann::json::array({q.w, q.x, q.y, q.z})},
                          {"velocity", vec3(b.velocity)},
                          {"angular_velocity", vec3(b.angularVelocity)}});
    }
    return bodies;
}

void writeSummary(const std::filesystem::path& file, const Scene& scene, const World& world,
                  const RunSummary& s, const std::vector<RankFigures>& ranks,
                  const std::vector<double>& rankPeakBytes) {
    const BackendKind backend = world.backend().kind();
    nlohmann::json j;
    j["pbf_version"] = kVersion;
    j["scene"] = scene.name;
    j["scene_file"] = scene.source;
    if (!scene.overrides.empty()) {  // `pbf export usd` loads the scene with them
        nlohmann::json overrides = nlohmann::json::array();
        for (const SceneOverride& o : scene.overrides) overrides.push_back(o.path + "=" + o.value);
        j["scene_overrides"] = overrides;
    }
    j["frames"] = s.frames;
    j["particles"] = s.particles;
    j["simulated_seconds"] = s.simulatedSeconds;
    j["wall_seconds"] = s.wallSeconds;
    j["output_seconds"] = s.outputSeconds;
    j["checkpoint_seconds"] = s.checkpointSeconds;
    j["substeps"] = s.substeps;
    j["particle_steps_per_second"] = s.particleStepsPerSecond;
    j["max_density_error"] = s.maxDensityError;
    j["average_density_error"] = s.averageDensityError;
    j["particle_radius"] = scene.simulation.particleRadius;  // read by `pbf mesh`
    j["fps"] = scene.fps;  // frame k is at k / fps: `pbf mesh` and the Blender add-on read it
    j["max_escaped"] = s.maxEscaped;
    j["max_inside_solid"] = s.maxInsideSolid;
    j["skipped_in_solids"] = s.skippedInSolids;
    // The water's balance: particles = the fluid blocks' + emitted - removed.
    j["emitted_particles"] = s.emitted;
    j["removed_particles"] = s.removed;
    j["resumed_from_frame"] = s.resumedFromFrame;
    j["interrupted"] = s.interrupted;
    j["backend"] = std::string(backendName(backend));
    // Distributed runs (docs/distributed.md): processes and each one's
    // particles at the end (1 and [particles] in one process).
    // Each rank's share (the last step's ghosts, peers and bytes sent).
    j["ranks"] = ranks.size();
    std::vector<std::uint64_t> particles, ghosts, peers, bytes;
    for (const RankFigures& r : ranks) {
        particles.push_back(r.particles);
        ghosts.push_back(r.ghosts);
        peers.push_back(r.peers);
        bytes.push_back(r.bytesSent);
    }
    j["rank_particles"] = particles;
    j["rank_ghosts"] = ghosts;
    j["rank_peers"] = peers;
    j["rank_bytes_sent_per_substep"] = bytes;
    std::vector<double> peakMiB;
    for (double peak : rankPeakBytes) peakMiB.push_back(std::round(peak / (1 << 20)));
    j["rank_peak_memory_mib"] = peakMiB;
    if (world.bodyCount() > 0) j["bodies"] = bodiesJson(world);
    if (s.error) j["error"] = s.error->message;
    writeFileAtomically(file, [&](std::ostream& out) {
        out << j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) << "\n";
    });
}

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

constexpr double kMiB = 1024.0 * 1024.0;

// Adds the wall time of its scope to `total` (seconds).
class OutputTimer {
  public:
    explicit OutputTimer(double& total) : total_(total) {}
    ~OutputTimer() { total_ += std::chrono::duration<double>(Clock::now() - start_).count(); }
    OutputTimer(const OutputTimer&) = delete;
    OutputTimer& operator=(const OutputTimer&) = delete;

  private:
    double& total_;
    Clock::time_point start_ = Clock::now();
};

// Bytes of one PLY frame (header and 32 bytes per particle).
std::uintmax_t plyBytes(std::size_t particles) {
    return 512 + std::uintmax_t{particles} * 32;
}

// Bytes of one .vtu frame: 32 per particle as in the PLY, a vertex cell
// (Int64 connectivity and offset at most, a type byte) and the header.
std::uintmax_t vtuBytes(std::size_t particles) {
    return 2048 + std::uintmax_t{particles} * (32 + 17);
}

// Bytes of the per-frame files the scene's output asks for.
std::uintmax_t frameBytes(const OutputParams& output, std::size_t particles) {
    return (output.writeParticles ? plyBytes(particles) : 0) +
           (output.writeVtk ? vtuBytes(particles) + 128 : 0) +  // + a .pvd entry
           (output.writeH5Part ? 4096 + std::uintmax_t{particles} * 36 : 0);
}

constexpr const char* kCollectionName = "particles.pvd";
constexpr const char* kH5PartIndexName = "particles.h5part";

fs::path vtuFileName(int frame) {
    return frameFileName(frame).replace_extension(".vtu");
}
fs::path h5partFileName(int frame) {
    return frameFileName(frame).replace_extension(".h5part");
}

}  // namespace

RunDriver::RunDriver(const Scene& scene, const RunOptions& options)
    : scene_(scene),
      options_(options),
      output_(scene.output),
      dir_(scene.output.directory),
      writer_(distributed::rank() == 0),
      world_(scene, options.world) {}

void RunDriver::createDirectory() const {
    if (!writer_) return;
    std::error_code ec;
    fs::create_directories(dir_, ec);
    if (ec || !fs::is_directory(dir_))
        throw IoError(dir_.string() + ": cannot create output directory" +
                      (ec ? " (" + ec.message() + ")" : ""));
}

// A run killed while writing leaves the temporary file of writeFileAtomically
// (".frame_00012.ply.tmp123456"); the file it was to replace is whole.
void RunDriver::removeStaleTemporaries() const {
    if (!writer_) return;
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
    removeStaleTemporaries();
    // A failure is every rank's failure.
    std::error_code ec;
    if (distributed::anyRank(writer_ && !fs::exists(file, ec)))
        throw IoError(file.string() +
                      ": no checkpoint to resume from; run without --resume to start at frame 0");
    // Each rank reads its share of the particles (all of them in one process).
    Checkpoint checkpoint = readCheckpointFromRanks(file);
    restoreCheckpoint(checkpoint, world_, scene_.fingerprint, file.string());
    totals_ = std::move(checkpoint.totals);
    previousWallSeconds_ = totals_.wallSeconds;
    summary_.resumedFromFrame = world_.frame();
    lastCheckpointFrame_ = world_.frame();
    summary_.checkpoint = file;
    // stats.csv may hold rows of frames computed after the checkpoint by the
    // killed run: put it back to the checkpoint's rows; they are recomputed.
    if (!writer_) return;
    writeFileAtomically(dir_ / "stats.csv", [&](std::ostream& out) { out << totals_.statsCsv; });
    if (output_.writeVtk) restoreCollection();
    if (world_.bodyCount() > 0)
        writeFileAtomically(dir_ / "bodies.csv",
                            [&](std::ostream& out) { out << totals_.bodiesCsv; });
    notice(world_.frame() >= output_.frames
               ? fmt::format("{} is at frame {}: nothing left to simulate up to frame {}",
                             file.string(), world_.frame(), output_.frames)
               : fmt::format("resuming from frame {} of {} ({})", world_.frame(), output_.frames,
                             file.string()));
}

void RunDriver::warnIfDiskTooSmall() const {
    if (!writer_) return;
    std::error_code ec;
    const fs::space_info space = fs::space(dir_, ec);
    const int remaining = output_.frames - world_.frame();
    if (ec || remaining <= 0) return;
    const std::size_t n = world_.particleCount();
    const double needed =
        double(frameBytes(output_, n)) * remaining +
        double(checkpointBytes(n, totals_.statsCsv.size() + totals_.bodiesCsv.size()));
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
    if (!writer_) return;
    std::error_code ec;
    const fs::space_info space = fs::space(dir_, ec);
    if (ec) return;  // unknown (some network file systems): the writes report failures
    const std::size_t n = world_.particleCount();
    const std::uintmax_t frame = frameBytes(output_, n) + 512;  // + a stats row
    const std::uintmax_t needed =
        frame + checkpointBytes(n, totals_.statsCsv.size() + totals_.bodiesCsv.size());
    if (space.available < needed + options_.reserveBytes)
        throw IoError(
            fmt::format("{}: output disk full: {:.1f} MiB free, but the next frame and its "
                        "checkpoint need {:.1f} MiB and "
                        "{:.1f} MiB are kept in reserve; free space or choose another --out, then "
                        "continue with --resume",
                        dir_.string(), double(space.available) / kMiB, double(needed) / kMiB,
                        double(options_.reserveBytes) / kMiB));
}

void RunDriver::startStats() {
    totals_.statsCsv = statsCsvHeader() + "\n";
    if (!writer_) return;
    writeFileAtomically(dir_ / "stats.csv", [&](std::ostream& out) { out << totals_.statsCsv; });
    if (world_.bodyCount() == 0) return;
    totals_.bodiesCsv = bodiesCsvHeader() + "\n";
    writeFileAtomically(dir_ / "bodies.csv", [&](std::ostream& out) { out << totals_.bodiesCsv; });
}

void RunDriver::record(const FrameReport& report) {
    const OutputTimer timer(summary_.outputSeconds);
    checkFreeSpace();
    // Distributed: gathering the particles on rank 0 (VTK, pictures) takes
    // every rank; the PLY frames are written by all ranks at once.
    if (distributed::anyRank(output_.writeVtk || bool(options_.writeFrame))) world_.particles();
    if (output_.writeParticles)
        writeParticlesPlyFromRanks(dir_ / frameFileName(report.frame), world_.ownParticles());
    if (output_.writeH5Part) writeH5PartFrame(report.frame);
    const std::string row = statsCsvRow(report) + "\n";
    totals_.statsCsv += row;
    const std::string bodyRows = world_.bodyCount() > 0 ? bodiesCsvRows(world_) : "";
    totals_.bodiesCsv += bodyRows;
    if (writer_) {
        if (output_.writeVtk) writeVtkFrame(report.frame);
        if (options_.writeFrame) options_.writeFrame(report.frame, world_);
        appendToFile(dir_ / "stats.csv", row);
        if (!bodyRows.empty()) appendToFile(dir_ / "bodies.csv", bodyRows);
    }
    totals_.maxDensityError = std::max(totals_.maxDensityError, report.state.maxDensityError);
    totals_.maxEscaped = std::max<std::uint64_t>(totals_.maxEscaped, report.state.escaped);
    totals_.maxInsideSolid =
        std::max<std::uint64_t>(totals_.maxInsideSolid, report.state.insideSolid);
    totals_.densityErrorSum += report.state.averageDensityError;
    totals_.substeps += report.substeps;
    totals_.solverMilliseconds += report.stageMs.total;
    if (options_.onFrame) options_.onFrame(report);
}

// The frame's file, written by all ranks (each its own particles, in rank
// order), then the index listing the frames so far (rank 0): the index
// never lists a file that is not whole.
void RunDriver::writeH5PartFrame(int frame) {
    const ParticleStore& own = world_.ownParticles();
    writeH5PartFile(dir_ / h5partFileName(frame), frame, frame / double(scene_.fps), own,
                    distributed::sumOverRanksBefore(own.size()),
                    distributed::sumOverRanks(own.size()), H5PartComm::run());
    if (!writer_) return;
    std::vector<fs::path> frames;
    for (int k = 0; k <= frame; ++k)
        if (std::error_code ec; fs::exists(dir_ / h5partFileName(k), ec))
            frames.push_back(h5partFileName(k));
    writeH5PartIndex(dir_ / kH5PartIndexName, frames);
}

// The .vtu file, then its entry in particles.pvd: the collection never lists
// a file that is not whole. Frame 0 starts a new collection.
void RunDriver::writeVtkFrame(int frame) {
    const double time = frame / double(scene_.fps);
    vtk::writeParticlesVtu(dir_ / vtuFileName(frame), world_.particles(), time);
    const vtk::CollectionEntry entry{time, vtuFileName(frame).string()};
    if (frame == 0)
        vtk::writeCollection(dir_ / kCollectionName, {entry});
    else
        vtk::appendToCollection(dir_ / kCollectionName, entry);
}

// On resume the collection may list frames the killed run wrote after its
// checkpoint; they are simulated again and appended again, so the list is
// rewritten to the frames up to the checkpoint (those whose .vtu exists:
// the run may have been started without VTK output).
void RunDriver::restoreCollection() const {
    std::vector<vtk::CollectionEntry> entries;
    std::error_code ec;
    for (int frame = 0; frame <= world_.frame(); ++frame)
        if (fs::exists(dir_ / vtuFileName(frame), ec))
            entries.push_back({frame / double(scene_.fps), vtuFileName(frame).string()});
    vtk::writeCollection(dir_ / kCollectionName, entries);
}

// The state is captured only here, when a checkpoint is due (not every frame).
void RunDriver::saveCheckpoint() {
    const OutputTimer timer(summary_.checkpointSeconds);
    // Each rank its own part of the particles, written by all at once.
    Checkpoint checkpoint = captureCheckpoint(world_, scene_.fingerprint, true);
    checkpoint.totals = totals_;
    checkpoint.totals.wallSeconds = wallSeconds();
    const fs::path file = dir_ / kCheckpointFileName;
    writeCheckpointFromRanks(file, checkpoint);
    summary_.checkpoint = file;
    lastCheckpointFrame_ = world_.frame();
    lastCheckpointTime_ = Clock::now();
}

bool RunDriver::checkpointDue() const {
    if (!output_.writeCheckpoints) return false;
    const int frames = world_.frame() - lastCheckpointFrame_;
    const double seconds =
        std::chrono::duration<double>(Clock::now() - lastCheckpointTime_).count();
    // Ranks' clocks differ: checkpoint when any rank finds it due.
    return distributed::anyRank(
        (output_.checkpointEvery > 0 && frames >= output_.checkpointEvery) ||
        (output_.checkpointSeconds > 0.0 && seconds >= output_.checkpointSeconds));
}

// A frame failed: the frames before it are written; the world holds the
// failing state, so nothing is checkpointed now. The last checkpoint (if
// any) is where the run can be continued from.
void RunDriver::fail(StepError error) {
    const int lastGood = error.frame - 1;
    std::string where;
    if (!summary_.checkpoint.empty() && lastCheckpointFrame_ >= 0)
        where = fmt::format(
            "; continue from the checkpoint of frame {} ({}) with --resume after raising "
            "guard.max_speed or changing the settings",
            lastCheckpointFrame_, summary_.checkpoint.string());
    else
        where = "; there is no checkpoint yet: change the scene and run again from frame 0";
    error.message = fmt::format("{}; the run stopped: frames up to {} are written{}", error.message,
                                lastGood, where);
    summary_.error = std::move(error);
}

RunSummary RunDriver::run() {
    createDirectory();
    summary_.skippedInSolids = world_.skippedParticles();
    if (options_.onStart) options_.onStart(world_);
    if (options_.resume) {
        resumeFromCheckpoint();
    } else {
        startStats();
        record(world_.report());
        lastCheckpointFrame_ = 0;  // frame 0 is recreated from the scene; no checkpoint needed
    }
    warnIfDiskTooSmall();
    while (world_.frame() < output_.frames) {
        // A signal may reach the ranks at different frames: stop together.
        if (distributed::anyRank(options_.stopRequested && options_.stopRequested())) {
            summary_.interrupted = true;
            break;
        }
        FrameResult result = world_.stepFrame();
        if (!result.ok()) {
            fail(std::move(*result.error));
            break;
        }
        record(result.report);
        if (checkpointDue()) saveCheckpoint();
    }
    if (!summary_.error && output_.writeCheckpoints &&
        (lastCheckpointFrame_ != world_.frame() || summary_.checkpoint.empty()))
        saveCheckpoint();
    return finish();
}

RunSummary RunDriver::finish() {
    RunSummary& s = summary_;
    const int completed = s.error ? s.error->frame - 1 : world_.frame();
    s.frames = completed;
    s.lastFrame = completed;
    s.particles = world_.particleCount();
    s.emitted = world_.emittedParticles();
    s.removed = world_.removedParticles();
    s.simulatedSeconds = completed * world_.frameDuration();
    s.wallSeconds = wallSeconds();
    s.substeps = totals_.substeps;
    s.maxDensityError = totals_.maxDensityError;
    s.maxEscaped = static_cast<std::size_t>(totals_.maxEscaped);
    s.maxInsideSolid = static_cast<std::size_t>(totals_.maxInsideSolid);
    s.averageDensityError = totals_.densityErrorSum / (completed + 1);
    s.particleStepsPerSecond =
        totals_.solverMilliseconds > 0.0
            ? double(s.particles) * double(s.substeps) / (totals_.solverMilliseconds * 1e-3)
            : 0.0;
    const std::vector<RankFigures> rankFigures = world_.backend().rankFigures();
    const std::vector<double> rankPeakBytes = distributed::valuesOfRanks(double(peakResidentBytes()));
    if (writer_) writeSummary(dir_ / "summary.json", scene_, world_, s, rankFigures, rankPeakBytes);
    return s;
}

}  // namespace pbf::detail
