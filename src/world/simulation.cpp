#include "pbf/simulation.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

#include "pbf/state_guard.hpp"

namespace pbf {

Simulation::Simulation(const Scene& scene)
    : scene_(scene),
      solids_(buildSolids(scene)),
      particles_(createParticles(scene, solids_.get(), &skipped_)),
      solver_(scene.simulation, solids_),
      speedLimit_(pbf::speedLimit(scene)) {
    for (const EmitterDescription& e : scene.emitters) emitters_.emplace_back(e, scene.simulation);
}

void Simulation::setParams(const SimulationParams& params) {
    if (const std::string problem = validate(params); !problem.empty()) throw SceneError(problem);
    try {
        solver_.setParams(params);
    } catch (const std::invalid_argument& e) {
        throw SceneError(e.what());
    }
    scene_.simulation = params;  // the adaptive substep reads cfl and limits from here
}

void Simulation::restore(ParticleStore particles, int frame, double time,
                         const std::vector<EmitterState>& emitters) {
    if (emitters.size() != emitters_.size())
        throw std::invalid_argument("Simulation::restore: " + std::to_string(emitters.size()) +
                                    " emitter states for " + std::to_string(emitters_.size()) +
                                    " emitters");
    for (std::size_t k = 0; k < emitters.size(); ++k) emitters_[k].setState(emitters[k]);
    particles_ = std::move(particles);
    frame_ = frame;
    time_ = time;
}

void Simulation::checkState(int substep, double time, const char* stage) const {
    const std::optional<BadParticle> bad = findBadParticle(particles_, speedLimit_);
    if (!bad) return;
    const int frame = frame_ + 1;
    std::string message = fmt::format(
        "bad state in frame {} substep {} ({}, t = {:.6f} s): particle id {} at ({:.6g}, {:.6g}, "
        "{:.6g}): {}",
        frame, substep, stage, time, bad->id, bad->position.x, bad->position.y, bad->position.z,
        bad->problem);
    throw StateError(message, frame, substep, stage, *bad);
}

double Simulation::adaptiveSubstep(double remaining) const {
    const SolverParams& s = scene_.simulation.solver;
    const double maxDt = s.maxTimeStep;
    const double speed = double(maxSpeed(particles_)) + length(scene_.simulation.gravity) * maxDt;
    double dt = maxDt;
    if (speed > 0.0) dt = std::min(dt, s.cfl * scene_.simulation.particleSpacing() / speed);
    dt = std::max(dt, frameDuration() / s.maxSubsteps);
    const double steps = std::max(1.0, std::ceil(remaining / dt - 1e-6));
    return remaining / steps;
}

FrameReport Simulation::advanceFrame() {
    const SolverParams& s = scene_.simulation.solver;
    const double frameDt = frameDuration();
    FrameReport report;
    double remaining = frameDt;
    int substeps = 0;
    // The guard runs on the state handed in (a user or a resumed checkpoint
    // may have put NaN there) and after every substep, so no bad state
    // reaches the frame's outputs.
    checkState(0, time_, "before the first solver step of the frame");
    double elapsed = 0.0;
    while (remaining > 1e-12 * frameDt) {
        double dt = s.timeStepMode == TimeStepMode::Fixed ? frameDt / s.fixedSubsteps
                                                          : adaptiveSubstep(remaining);
        if (dt > remaining * (1.0 - 1e-9)) dt = remaining;  // last step ends the frame exactly
        const double stepStart = time_ + (frameDt - remaining);
        for (Emitter& emitter : emitters_) emitter.emit(stepStart, dt, particles_, solids_.get());
        solver_.step(particles_, static_cast<float>(dt));
        report.stageMs += solver_.lastStageTimes();
        remaining -= dt;
        elapsed += dt;
        ++substeps;
        checkState(substeps, frame_ * frameDt + elapsed, "after solver step");
    }
    ++frame_;
    time_ = frame_ * frameDt;  // no drift from summing substeps
    const FrameReport state = this->report();
    report.frame = state.frame;
    report.time = state.time;
    report.iterations = state.iterations;
    report.state = state.state;
    report.substeps = substeps;
    report.stepMs = substeps > 0 ? report.stageMs.total / substeps : 0.0;
    return report;
}

FrameReport Simulation::report() const {
    FrameReport r;
    r.frame = frame_;
    r.time = time_;
    r.iterations = scene_.simulation.solver.iterations;
    r.state = computeStatistics(particles_, solver_.constants(), scene_.simulation.domain,
                                solids_.get(), scene_.simulation.particleRadius);
    return r;
}

}  // namespace pbf
