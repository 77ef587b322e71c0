// The viewer's simulation thread: steps a pbf::World while the UI thread
// draws, so that a slow step never stalls the window. The UI sends commands
// (play, pause, step, reset, new settings) and takes the latest published
// snapshot; neither thread waits for the other's work. A frame that fails
// (the state guard, after a settings change say) pauses the worker and is
// reported by lastError(); it steps again after a reset.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "pbf/io/scene.hpp"
#include "pbf/world/world.hpp"

namespace pbf::render {

// One published state: positions, speeds and densities of all particles.
struct Snapshot {
    std::uint64_t version = 0;  // increases with every publication
    std::vector<float> xyz;     // 3 floats per particle
    std::vector<float> speed;
    std::vector<float> density;
    FrameReport report;
    double frameMs = 0.0;  // wall-clock ms of the last simulated frame
    // The backend that computed it (World::backend().kind()).
    BackendKind device = BackendKind::Cpu;
    // Pose of each rigid body's surface (the pose of its solid in
    // World::solids(), for render::tessellateBodyShapes' meshes).
    std::vector<Pose> bodyPoses;
};

class SimulationWorker {
  public:
    // Steps a World of `scene` on `device` (WorldOptions::backend).
    SimulationWorker(const Scene& scene, bool playing, BackendKind device = BackendKind::Cpu);
    ~SimulationWorker();
    SimulationWorker(const SimulationWorker&) = delete;
    SimulationWorker& operator=(const SimulationWorker&) = delete;

    void setPlaying(bool playing);
    bool playing() const { return playing_; }
    void requestStep();   // one frame, when paused
    void requestReset();  // back to the scene's initial state (keeps current parameters)
    // Applied between frames (World::applySettings); an invalid set is
    // refused and reported by lastError().
    void setParams(const SimulationParams& params);
    // Plays until the simulation has completed `frame` frames, then pauses.
    void pauseAt(int frame);

    // Copies the newest snapshot into `out` if it is newer than out.version.
    bool takeSnapshot(Snapshot& out) const;
    int framesSimulated() const { return frames_; }
    double averageFrameMs() const;
    std::string lastError() const;
    // A frame failed; no more steps until requestReset().
    bool failed() const { return failed_; }

  private:
    void run();
    void publish(const World& world, const FrameReport* stepped, double frameMs);
    void applyPendingSettings(World& world);
    void stepOneFrame(World& world);

    WorldDef definition_;
    WorldOptions worldOptions_;
    std::atomic<bool> playing_;
    std::atomic<bool> quit_{false};
    std::atomic<int> stepRequests_{0};
    std::atomic<bool> resetRequest_{false};
    std::atomic<int> pauseAt_{-1};
    std::atomic<int> frames_{0};
    std::atomic<bool> failed_{false};

    mutable std::mutex mutex_;  // guards everything below
    std::condition_variable wake_;
    std::optional<SimulationParams> pendingParams_;
    Snapshot snapshot_;
    double totalFrameMs_ = 0.0;
    int timedFrames_ = 0;
    std::string error_;

    std::thread thread_;  // last: starts after every member is ready
};

}  // namespace pbf::render
