// pbf::World: one simulation — its definition, its live settings, its state
// and the one frame loop that advances it.
//
//   pbf::WorldDef def;                        // or: pbf::loadScene("scenes/dam_break.json")
//   def.simulation.domain = {{0, 0, 0}, {1, 1, 1}};
//   def.fluidBlocks.push_back({{{0, 0, 0}, {0.3f, 0.5f, 1}}});
//   pbf::World world(def);
//   pbf::FrameResult r = world.stepFrame();   // 1 / fps simulated seconds
//   if (!r.ok()) std::cerr << r.error->message;
//
// stepFrame() is the only place where solver steps are driven: it chooses
// the substeps (CFL-limited or fixed), runs the emitters, asks the backend
// to step, and runs the state guard after every substep. Failures come back
// as values (FrameResult::error), so no exception crosses a thread: the CLI,
// the viewer's simulation thread and Python report them the same way.
//
// The particles live in the backend (include/pbf/backend/backend.hpp); the World
// reads them through the backend's reductions and downloads them only when
// asked (particles(), arraysById()).
//
// Coordinates: the API speaks world coordinates, as the definition does. The
// solver, solids() and the state (captureState) measure positions from the
// World's local frame (pbf/world/local_frame.hpp), which is the world's own
// for a domain near the origin and centred on the domain far from it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "pbf/backend/backend.hpp"
#include "pbf/backend/statistics.hpp"
#include "pbf/bodies/rigid_body.hpp"
#include "pbf/core/particles.hpp"
#include "pbf/core/solver_constants.hpp"
#include "pbf/core/state_guard.hpp"
#include "pbf/geometry/solids.hpp"
#include "pbf/world/emitter.hpp"
#include "pbf/world/local_frame.hpp"
#include "pbf/world/world_def.hpp"

namespace pbf {

namespace detail {
class RigidBodies;
}

struct FrameReport {
    int frame = 0;      // frames completed
    double time = 0.0;  // simulated seconds
    int substeps = 0;   // solver steps taken in this frame
    // Density iterations (corrections) per substep the solver ran, averaged
    // over the frame's substeps (counted in its loop: with
    // solver.max_density_error it varies).
    double iterations = 0.0;
    // Particles the emitters added and the outlets removed in this frame.
    std::size_t emitted = 0;
    std::size_t removed = 0;
    double stepMs = 0.0;  // average wall-clock ms per substep in this frame
    StageTimes stageMs;   // summed over the frame's substeps
    StateStatistics state;
};

// Why a frame could not be completed.
struct StepError {
    enum class Kind {
        BadState,  // the state guard fired: NaN / infinite values or a speed over the limit
        Failure,   // anything else (out of memory, ...)
    };
    Kind kind = Kind::Failure;
    std::string message;  // whole sentence: frame, substep, stage, particle id, problem
    int frame = 0;        // frame being computed (1-based, as in frame_NNNNN.ply)
    int substep = 0;      // substep within it (1-based; 0: before the first)
    std::string stage;    // where the check ran, e.g. "after solver step"
    std::optional<BadParticle> particle;
};

struct FrameResult {
    FrameReport report;              // valid when ok()
    std::optional<StepError> error;  // the world is left as the failing substep made it
    bool ok() const { return !error.has_value(); }
};

// Everything that changes while a world runs: enough to continue it
// bit-identically (a checkpoint). Positions (particles', bodies') are in the
// World's local frame: a far world's are not rounded to world floats.
struct WorldState {
    ParticleStore particles;             // the backend's memory order
    // A distributed rank's part (World::captureState(true)): `particles` are
    // the places [first, first + size) of the memory order of `total`
    // particles. total 0: `particles` are all of them.
    std::uint64_t first = 0;
    std::uint64_t total = 0;
    std::vector<EmitterState> emitters;  // one per emitter of the definition
    std::vector<RigidBodyState> bodies;  // one per rigid body of the definition
    std::uint64_t removed = 0;           // particles the outlets removed so far
    int frame = 0;
    double time = 0.0;
};

// Particle attributes in host memory in id order (entry k is the particle
// with the k-th smallest id: id k while no particle has left through an
// outlet): what scripting reads and writes. Buffers are shared so that
// views of them (numpy arrays) stay valid when the World replaces them
// after the particle count changed.
struct ParticleArrays {
    std::size_t count = 0;
    std::shared_ptr<std::vector<float>> position;    // 3 per particle, m
    std::shared_ptr<std::vector<float>> velocity;    // 3 per particle, m/s
    std::shared_ptr<std::vector<float>> density;     // kg/m^3 (read only)
    std::shared_ptr<std::vector<std::uint64_t>> id;  // ascending (read only)
};

struct WorldOptions {
    BackendKind backend = BackendKind::Cpu;
    BackendOptions backendOptions;
};

class World {
  public:
    // Builds the solids (loading meshes) and fills the fluid blocks. Throws
    // SceneError for an invalid definition and SceneError naming the
    // file and field for a broken mesh.
    explicit World(const WorldDef& def, const WorldOptions& options = {});
    ~World();
    World(World&&) noexcept;
    World& operator=(World&&) noexcept;

    const WorldDef& definition() const { return def_; }
    // Where positions are measured from inside (see the top of this file).
    const LocalFrame& localFrame() const { return local_; }

    // Live settings: the one copy of the parameters the solver runs with.
    // applySettings validates (SceneError naming the field, nothing
    // changed) and takes effect at the next step; the domain, particle
    // radius and kernel radius factor belong to the definition and cannot change.
    const SimulationParams& settings() const { return settings_; }
    void applySettings(const SimulationParams& settings);

    // Simulates one output frame (1 / fps seconds).
    FrameResult stepFrame();
    // Statistics of the current state (a reduction in the backend).
    FrameReport report() const;

    int frame() const { return frame_; }
    double time() const { return time_; }
    double frameDuration() const { return 1.0 / def_.fps; }
    std::size_t particleCount() const { return backend_->size(); }
    // Lattice sites of the fluid blocks left empty because a solid was there.
    std::size_t skippedParticles() const { return skipped_; }

    // The particles in the backend's memory order (downloaded when they are
    // not in host memory, copied to world coordinates when the local frame is
    // shifted). Valid until the next step.
    const ParticleStore& particles() const;
    // This process's particles: in a distributed run, this rank's own (no
    // gather; in no particular order), else all of them (particles()).
    // Valid until the next step.
    const ParticleStore& ownParticles() const;
    // The particles by id, for scripting; writes to position and velocity
    // take effect at the next step. Valid (and kept up to date after every
    // frame) until the particle count changes.
    ParticleArrays& arraysById();
    // Adds particles with the next free ids (densities start at rest density).
    void addParticles(std::span<const Vec3> positions, std::span<const Vec3> velocities);

    // The solids as the solver queries them: in the local frame.
    const SolidSet& solids() const { return *solids_; }
    // Solid i's pose and velocity in world coordinates.
    SolidMotion solidMotion(std::size_t i) const;
    // Moves solid i between frames (kinematic: the fluid sees its pose and
    // its velocity at contacts). Refused for a solid with a prescribed
    // motion (solids[i].motion), which the World places every substep.
    void setSolidMotion(std::size_t i, const SolidMotion& motion);
    const std::vector<Emitter>& emitters() const { return emitters_; }
    // Particles the outlets (definition().outlets) removed so far, and the
    // emitters added: particleCount() is the fluid blocks' particles plus
    // emitted minus removed, exactly.
    std::uint64_t removedParticles() const { return removed_; }
    std::uint64_t emittedParticles() const;

    // Rigid bodies (definition().rigidBodies, in that order): what each is,
    // its state, and the fluid's force and torque on it averaged over the
    // last frame. A body's surface is solid bodyInfos()[i].solid of solids().
    std::size_t bodyCount() const;
    const std::vector<RigidBodyInfo>& bodyInfos() const;
    const std::vector<RigidBodyState>& bodyStates() const;
    const std::vector<RigidBodyLoad>& bodyLoads() const;
    // Replaces body i's state between frames (scripting).
    void setBodyState(std::size_t i, const RigidBodyState& state);

    // Speed above which the state guard fails a frame (m/s; <= 0: no speed
    // check). Defaults to speedLimit(definition()).
    double speedLimit() const { return speedLimit_; }
    void setSpeedLimit(double metresPerSecond) { speedLimit_ = metresPerSecond; }

    // The substep the adaptive mode takes now, given `remaining` seconds of
    // the frame: min(max_time_step, cfl * spacing / speed), where speed is the
    // largest particle or body-surface speed plus what gravity adds in one
    // step (and, with fluid.kinematic_viscosity nu, at most 0.05 spacing^2 /
    // nu; with fixed iterations, depthStep), then evened out so that the
    // frame ends on a whole number of equal substeps.
    double adaptiveSubstep(double remaining) const;
    // solver.depth_limit's bound on a substep (s): the step at which water as
    // deep as the fluid blocks start stays at Pi = depth_limit (world.cpp);
    // infinite without gravity, with the limit at 0 or with a density
    // tolerance (max_density_error).
    double depthStep() const;

    // The state, for checkpoints; restoreState puts one back (particles in
    // their memory order: the solver's stable sort depends on it, so
    // resuming bit-identically needs the exact order; positions in the local
    // frame).
    // ownPart: in a distributed run, this rank's part of the particles only
    // (collective; no gather), which restoreState() takes back on any rank count.
    WorldState captureState(bool ownPart = false) const;
    void restoreState(WorldState state);

    const SolverConstants& constants() const { return constants_; }
    const Backend& backend() const { return *backend_; }
    Backend& backend() { return *backend_; }

  private:
    SolverContext context() const;
    std::optional<StepError> checkState(int substep, double time, const char* stage) const;
    void applyHostEdits();
    void refreshArrays();
    void indexSolids();
    // The fluid blocks' particles into the backend (each rank its share when distributed).
    void createParticles();
    void placeDrivenSolids(double time);

    WorldDef def_;
    LocalFrame local_;
    WorldDef localDef_;               // def_ in the local frame: what the solver and the solids see
    SimulationParams settings_;       // world coordinates (the domain as defined)
    SimulationParams localSettings_;  // settings_ with the domain in the local frame
    SolverConstants constants_;
    std::unique_ptr<SolidSet> solids_;
    std::unique_ptr<detail::RigidBodies> bodies_;
    std::unique_ptr<Backend> backend_;
    std::vector<Emitter> emitters_;
    std::vector<OutletRegion> outlets_;  // in the local frame
    std::uint64_t removed_ = 0;
    // Solids with a prescribed motion: their index, pose at rest and pivot
    // (local frame), and the fastest point of any of them now (m/s).
    struct DrivenSolid {
        std::size_t index = 0;
        Pose rest;
        Vec3 pivot;
    };
    std::vector<DrivenSolid> driven_;
    double drivenSpeed_ = 0.0;
    // The fluid blocks' extent along gravity at the start (m): the depth
    // solver.depth_limit is applied to.
    double startDepth_ = 0.0;
    std::size_t skipped_ = 0;
    int frame_ = 0;
    double time_ = 0.0;
    double speedLimit_ = 0.0;
    mutable ParticleStore downloaded_;  // particles() for backends without host state
    mutable bool downloadedValid_ = false;
    mutable ParticleStore ownDownloaded_;  // ownParticles() of a distributed rank
    mutable bool ownValid_ = false;
    std::unique_ptr<ParticleArrays> arrays_;  // exists once arraysById() was called
    // The positions arraysById() last showed, when the frame is shifted: only
    // those a script changed are written back (a world float rounds a far
    // particle's position).
    std::vector<float> shownPositions_;
    mutable std::vector<RigidBodyState> worldBodyStates_;  // bodyStates() when shifted
};

}  // namespace pbf
