#include "sim_worker.hpp"

#include <chrono>

namespace pbf::render {

SimulationWorker::SimulationWorker(const Scene& scene, bool playing, BackendKind device)
    : definition_(scene), worldOptions_{device, {}}, playing_(playing), thread_([this] {
          run();
      }) {}

SimulationWorker::~SimulationWorker() {
    quit_ = true;
    wake_.notify_all();
    thread_.join();
}

void SimulationWorker::setPlaying(bool playing) {
    playing_ = playing;
    wake_.notify_all();
}

void SimulationWorker::requestStep() {
    ++stepRequests_;
    wake_.notify_all();
}

void SimulationWorker::requestReset() {
    resetRequest_ = true;
    wake_.notify_all();
}

void SimulationWorker::setParams(const SimulationParams& params) {
    {
        std::lock_guard lock(mutex_);
        pendingParams_ = params;
    }
    wake_.notify_all();
}

void SimulationWorker::pauseAt(int frame) {
    pauseAt_ = frame;
    playing_ = true;
    wake_.notify_all();
}

bool SimulationWorker::takeSnapshot(Snapshot& out) const {
    std::lock_guard lock(mutex_);
    if (snapshot_.version == out.version) return false;
    out = snapshot_;
    return true;
}

double SimulationWorker::averageFrameMs() const {
    std::lock_guard lock(mutex_);
    return timedFrames_ > 0 ? totalFrameMs_ / timedFrames_ : 0.0;
}

std::string SimulationWorker::lastError() const {
    std::lock_guard lock(mutex_);
    return error_;
}

void SimulationWorker::publish(const World& world, const FrameReport* stepped, double frameMs) {
    const ParticleStore& p = world.particles();
    const std::size_t n = p.size();
    Snapshot s;
    s.xyz.resize(3 * n);
    s.speed.resize(n);
    s.density = p.density;
    for (std::size_t i = 0; i < n; ++i) {
        s.xyz[3 * i + 0] = p.position.x[i];
        s.xyz[3 * i + 1] = p.position.y[i];
        s.xyz[3 * i + 2] = p.position.z[i];
        s.speed[i] = length(p.velocity.get(i));
    }
    s.report = stepped != nullptr ? *stepped : world.report();
    s.frameMs = frameMs;
    s.device = world.backend().kind();
    for (const RigidBodyInfo& body : world.bodyInfos())
        s.bodyPoses.push_back(world.solidMotion(body.solid).pose);
    std::lock_guard lock(mutex_);
    s.version = snapshot_.version + 1;
    snapshot_ = std::move(s);
}

void SimulationWorker::applyPendingSettings(World& world) {
    std::optional<SimulationParams> params;
    {
        std::lock_guard lock(mutex_);
        params.swap(pendingParams_);
    }
    if (!params) return;
    std::string error;
    try {
        world.applySettings(*params);
    } catch (const std::exception& e) {
        error = e.what();
    }
    std::lock_guard lock(mutex_);
    error_ = error;
}

void SimulationWorker::stepOneFrame(World& world) {
    using Clock = std::chrono::steady_clock;
    const auto t0 = Clock::now();
    const FrameResult result = world.stepFrame();
    const double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    if (!result.ok()) {
        // The world holds the failing state: stop here, say why, keep the
        // last good snapshot on screen until a reset.
        failed_ = true;
        playing_ = false;
        stepRequests_ = 0;
        std::lock_guard lock(mutex_);
        error_ = result.error->message;
        return;
    }
    frames_ = world.frame();
    {
        std::lock_guard lock(mutex_);
        totalFrameMs_ += ms;
        ++timedFrames_;
    }
    publish(world, &result.report, ms);
}

void SimulationWorker::run() {
    std::unique_ptr<World> world;
    try {
        world = std::make_unique<World>(definition_, worldOptions_);
    } catch (const std::exception& e) {
        failed_ = true;
        playing_ = false;
        std::lock_guard lock(mutex_);
        error_ = e.what();
    }
    if (world) publish(*world, nullptr, 0.0);
    while (!quit_) {
        if (world) applyPendingSettings(*world);
        if (resetRequest_.exchange(false) && world) {
            // Back to the initial state, with the settings in use now.
            const SimulationParams settings = world->settings();
            world = std::make_unique<World>(definition_, worldOptions_);
            world->applySettings(settings);
            frames_ = 0;
            failed_ = false;
            {
                std::lock_guard lock(mutex_);
                error_.clear();
            }
            publish(*world, nullptr, 0.0);
        }
        if (failed_) {  // requests made while failed are dropped, not queued
            stepRequests_ = 0;
            playing_ = false;
        }
        const int stopAt = pauseAt_;
        if (stopAt >= 0 && world && world->frame() >= stopAt) {
            playing_ = false;
            pauseAt_ = -1;
        }
        if (world && !failed_ && (playing_ || stepRequests_ > 0)) {
            if (stepRequests_ > 0) --stepRequests_;
            stepOneFrame(*world);
            continue;
        }
        std::unique_lock lock(mutex_);
        wake_.wait_for(lock, std::chrono::milliseconds(50));
    }
}

}  // namespace pbf::render
