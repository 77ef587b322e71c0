// The loop of `pbf run` (private header): step the world frame by frame,
// write the outputs, checkpoint when due, resume, stop on request or when a
// frame fails.
#pragma once

#include <chrono>
#include <cstddef>
#include <filesystem>
#include <string>

#include "pbf/io/checkpoint.hpp"
#include "pbf/run/run.hpp"
#include "pbf/world/world.hpp"

namespace pbf::detail {

class RunDriver {
  public:
    RunDriver(const Scene& scene, const RunOptions& options);

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
    void startStats();
    void record(const FrameReport& report);
    void writeVtkFrame(int frame);
    void writeH5PartFrame(int frame);
    void restoreCollection() const;
    bool checkpointDue() const;
    void saveCheckpoint();
    void fail(StepError error);
    RunSummary finish();
    double wallSeconds() const {
        return previousWallSeconds_ +
               std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    }

    const Scene& scene_;
    const RunOptions& options_;
    const OutputParams& output_;
    std::filesystem::path dir_;
    // Rank 0 writes the files; in a distributed run the other ranks compute
    // their key ranges and take part in the gathers (include/pbf/core/distributed.hpp).
    bool writer_;
    World world_;
    // Totals for summary.json; statsCsv holds every row so far (the file is
    // appended to, the checkpoint carries the rows so that a resume can put
    // the file back to them).
    RunTotals totals_;
    RunSummary summary_;
    std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
    double previousWallSeconds_ = 0.0;  // wall time of the sessions before a resume
    std::chrono::steady_clock::time_point lastCheckpointTime_ = std::chrono::steady_clock::now();
    int lastCheckpointFrame_ = -1;
};

}  // namespace pbf::detail
