#include "sim_worker.hpp"

#include <chrono>

namespace pbf::render {

SimulationWorker::SimulationWorker(const Scene& scene, bool playing)
    : scene_(scene), playing_(playing), thread_([this] { run(); }) {}

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

void SimulationWorker::publish(const Simulation& simulation, const FrameReport* stepped,
                               double frameMs) {
    const ParticleStore& p = simulation.particles();
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
    s.report = stepped != nullptr ? *stepped : simulation.report();
    s.frameMs = frameMs;
    std::lock_guard lock(mutex_);
    s.version = snapshot_.version + 1;
    snapshot_ = std::move(s);
}

void SimulationWorker::run() {
    using Clock = std::chrono::steady_clock;
    auto simulation = std::make_unique<Simulation>(scene_);
    publish(*simulation, nullptr, 0.0);
    while (!quit_) {
        std::optional<SimulationParams> params;
        {
            std::lock_guard lock(mutex_);
            params.swap(pendingParams_);
        }
        if (params) {
            try {
                simulation->setParams(*params);
                scene_.simulation = *params;
                std::lock_guard lock(mutex_);
                error_.clear();
            } catch (const std::exception& e) {
                std::lock_guard lock(mutex_);
                error_ = e.what();
            }
        }
        if (resetRequest_.exchange(false)) {
            simulation = std::make_unique<Simulation>(scene_);
            frames_ = 0;
            publish(*simulation, nullptr, 0.0);
        }
        const int stopAt = pauseAt_;
        if (stopAt >= 0 && simulation->frame() >= stopAt) {
            playing_ = false;
            pauseAt_ = -1;
        }
        if (playing_ || stepRequests_ > 0) {
            if (stepRequests_ > 0) --stepRequests_;
            const auto t0 = Clock::now();
            const FrameReport report = simulation->advanceFrame();
            const double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
            frames_ = simulation->frame();
            {
                std::lock_guard lock(mutex_);
                totalFrameMs_ += ms;
                ++timedFrames_;
            }
            publish(*simulation, &report, ms);
            continue;
        }
        std::unique_lock lock(mutex_);
        wake_.wait_for(lock, std::chrono::milliseconds(50));
    }
}

}  // namespace pbf::render
