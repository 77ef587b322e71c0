// Drives the solver frame by frame: chooses substeps (CFL-limited or fixed),
// keeps simulated time, and reports per-frame statistics.
#pragma once

#include <cstddef>
#include <memory>
#include <vector>

#include "pbf/emitter.hpp"
#include "pbf/particles.hpp"
#include "pbf/scene.hpp"
#include "pbf/solver.hpp"
#include "pbf/statistics.hpp"

namespace pbf {

struct FrameReport {
    int frame = 0;        // frames completed
    double time = 0.0;    // simulated seconds
    int substeps = 0;     // solver steps taken in this frame
    int iterations = 0;   // density iterations per substep
    double stepMs = 0.0;  // average wall-clock ms per substep in this frame
    StageTimes stageMs;   // summed over the frame's substeps
    StateStatistics state;
};

class Simulation {
  public:
    // Builds the solids (loading meshes) and fills the fluid blocks; throws
    // SceneError for a broken mesh.
    explicit Simulation(const Scene& scene);

    const Scene& scene() const { return scene_; }
    const ParticleStore& particles() const { return particles_; }
    ParticleStore& particles() { return particles_; }
    Solver& solver() { return solver_; }
    const Solver& solver() const { return solver_; }
    int frame() const { return frame_; }
    double time() const { return time_; }
    double frameDuration() const { return 1.0 / scene_.output.fps; }
    // Lattice sites of the fluid blocks left empty because a solid was there.
    std::size_t skippedParticles() const { return skipped_; }
    const std::vector<Emitter>& emitters() const { return emitters_; }
    const SolidSet* solids() const { return solids_.get(); }

    // Changes parameters between frames (iterations, CFL, viscosity, vorticity,
    // s_corr, ...: what Solver::setParams allows; the viewer's live panel).
    // Throws SceneError when validate() rejects them or when they change the
    // domain, particle radius or kernel factor.
    void setParams(const SimulationParams& params);

    // Simulates one output frame (1 / fps seconds) and reports on it.
    // Throws StateError (include/pbf/state_guard.hpp) when the state is bad
    // before the frame or after any of its substeps; the particles are then
    // left as the failing step made them.
    FrameReport advanceFrame();
    // Statistics of the current state (frame 0 before any step).
    FrameReport report() const;

    // The substep the adaptive mode takes now, given `remaining` seconds of
    // the frame: min(max_time_step, cfl * spacing / speed), where speed is the
    // largest particle speed plus what gravity adds in one step, then evened
    // out so that the frame ends on a whole number of equal substeps.
    double adaptiveSubstep(double remaining) const;

    // Speed above which the state guard stops the run (m/s; <= 0: no speed
    // check). Defaults to speedLimit(scene).
    double speedLimit() const { return speedLimit_; }
    void setSpeedLimit(double metresPerSecond) { speedLimit_ = metresPerSecond; }

    // Replaces the state by a saved one: the particles in their memory order
    // (the solver's stable sort depends on it, so resuming needs the exact
    // order for bit-identical results), the frame counter and the time.
    // `emitters` holds one state per emitter of the scene, in scene order.
    void restore(ParticleStore particles, int frame, double time,
                 const std::vector<EmitterState>& emitters = {});

  private:
    void checkState(int substep, double time, const char* stage) const;

    Scene scene_;
    std::shared_ptr<const SolidSet> solids_;
    std::size_t skipped_ = 0;
    ParticleStore particles_;
    Solver solver_;
    std::vector<Emitter> emitters_;
    int frame_ = 0;
    double time_ = 0.0;
    double speedLimit_ = 0.0;
};

}  // namespace pbf
