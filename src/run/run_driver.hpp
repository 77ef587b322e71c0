// The loop of `pbf run` (private header): simulate frame by frame, write the
// outputs, checkpoint, resume, stop on request or when the state guard fires.
#pragma once

#include <chrono>
#include <cstddef>
#include <filesystem>
#include <string>

#include "pbf/checkpoint.hpp"
#include "pbf/run.hpp"
#include "pbf/simulation.hpp"

namespace pbf::detail {

// One run: the simulation, the totals for summary.json and stats.csv, the
// last good state (saved when the state guard fires) and the checkpoints.
class RunDriver {
  public:
    RunDriver(const Scene& scene, const RunOptions& options)
        : scene_(scene), options_(options), dir_(options.outputDirectory), simulation_(scene) {}

    RunSummary run();

  private:
    void notice(const std::string& message) const {
        if (options_.onNotice) options_.onNotice(message);
    }
    void createDirectory() const;
    void resumeFromCheckpoint();
    void removeStaleTemporaries() const;
    void warnIfDiskTooSmall() const;
    void checkFreeSpace() const;
    void record(const FrameReport& report);
    void advance();
    bool checkpointDue() const;
    void saveLastGood();
    double wallSeconds() const {
        return previousWallSeconds_ +
               std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    }

    const Scene& scene_;
    const RunOptions& options_;
    std::filesystem::path dir_;
    Simulation simulation_;
    RunTotals totals_;
    RunSummary summary_;
    Checkpoint lastGood_;  // state and totals after the last recorded frame
    std::size_t lastGoodCsvBytes_ = 0;
    std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
    double previousWallSeconds_ = 0.0;  // wall time of the sessions before a resume
    std::chrono::steady_clock::time_point lastCheckpointTime_ = std::chrono::steady_clock::now();
    int lastCheckpointFrame_ = -1;
};

}  // namespace pbf::detail
