// The backend seam: what a World asks of the solver that holds its particles.
//
// A backend owns the particle state wherever it lives (host memory for the
// CPU and reference backends; device memory or several processes for the
// backends to come) and advances it by one PBF step (Macklin & Mueller 2013,
// Algorithm 1). Everything the World needs between steps is asked of the
// backend as a reduction (largest speed, first bad particle, statistics) so
// that particle data crosses to the host only for output: hostState() gives
// zero-copy access where the particles are in host memory, download() a copy
// otherwise.
//
// Settings are not stored here: the World owns the one copy of the live
// settings and passes them, with the constants derived from them and the
// posed solids, to every call that needs them (SolverContext).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "pbf/backend/statistics.hpp"
#include "pbf/core/inlet_buffer.hpp"
#include "pbf/core/outlet_region.hpp"
#include "pbf/core/params.hpp"
#include "pbf/core/particles.hpp"
#include "pbf/core/solver_constants.hpp"
#include "pbf/core/state_guard.hpp"
#include "pbf/geometry/solids.hpp"

namespace pbf {

// Wall-clock milliseconds spent per part of a step, and the work done: one
// list (X(member, description)), from which the struct and its arithmetic
// are made. The solver's stages (backend/step_plan.hpp) each add their time
// to one phase (the first four) and, for the costly ones, to a part.
#define PBF_STAGE_TIMES(X)                                                                   \
    X(predict, "prediction, warm start and the swept collision with solids")                 \
    X(neighborSearch, "sort, reorder, neighbour lists")                                      \
    X(solve, "all density iterations")                                                       \
    X(postProcess, "velocity update, vorticity, XSPH, wall response")                        \
    X(total, "the whole step")                                                               \
    X(gridBuild, "part: cell of each particle + counting sort")                              \
    X(reorder, "part: permuting every particle array")                                       \
    X(neighborLists, "part: distance tests, neighbour lists")                                \
    X(lambda, "part: density + lambda passes, all iterations")                               \
    X(deltaP, "part: correction passes with their box / solid projection, all iterations")   \
    X(bodies, "rigid bodies: forces in, one Bullet step, poses out (the World adds it)")     \
    X(exchange,                                                                              \
      "distributed runs (backend/mpi): migration, ghost set-up and halo exchanges, waiting " \
      "for other ranks included (also in the phases above; 0 in one process)")               \
    X(iterations, "density iterations the solver ran (counted in its loop)")

struct StageTimes {
#define PBF_STAGE_TIME_MEMBER(member, description) double member = 0.0;
    PBF_STAGE_TIMES(PBF_STAGE_TIME_MEMBER)
#undef PBF_STAGE_TIME_MEMBER

    StageTimes& operator+=(const StageTimes& o);
    StageTimes operator*(double factor) const;
};

// What the fluid did to a coupled solid (a rigid body's surface) during one
// step: the reaction to the momentum the solid's boundary gave the fluid
// (src/backend/reactions.hpp). Force in N, torque in N m about the origin of
// the solid's frame (its pose's position).
struct SolidReaction {
    Vec3 force;
    Vec3 torque;
};

// The constant inputs of a backend call: the World's live settings, the SI
// constants derived from them, and the posed solids (null when there are none).
struct SolverContext {
    const SimulationParams& params;
    const SolverConstants& constants;
    const SolidSet* solids = nullptr;
};

enum class BackendKind {
    Cpu,        // SIMD CPU solver (Highway), OpenMP, deterministic: the default
    Reference,  // scalar, one function per equation of the paper: the test oracle
    Mpi,        // the CPU solver on one range of the cell key per MPI rank (builds with PBF_MPI)
    Cuda,       // the GPU backend on an NVIDIA GPU (builds with PBF_CUDA, nvcc)
    CudaOnCpu,  // the GPU backend's same source on the CPU (Thrust's OpenMP system)
};
// "cpu", "reference", "mpi", "cuda", "cuda-on-cpu".
std::string_view backendName(BackendKind kind);

// The most particles one process of a backend holds: the solvers index a
// process's particles with 32 bits (the sort's permutation, the neighbour
// lists, the GPU's kernels). Ids and counts over all processes are 64-bit.
inline constexpr std::size_t kMaxParticlesPerProcess = 0xFFFFFFFFu;
// Throws std::length_error naming the backend when a process of `kind`
// holding `held` particles would receive `added` more than that.
void checkParticlesPerProcess(BackendKind kind, std::size_t held, std::size_t added);
// Parses a device name as `--device` takes it (cpu, reference, cuda,
// cuda-on-cpu); throws std::invalid_argument listing the choices.
BackendKind parseBackendKind(std::string_view name);

// A device as this program can use it: whether it was built in, whether it
// can run here now, and what it is (or why not), e.g. "NVIDIA H100 80GB
// HBM3 (sm_90), 79.1 GiB of 79.6 GiB free" or "this pbf was built without CUDA ...".
struct DeviceInfo {
    BackendKind kind = BackendKind::Cpu;
    bool built = false;
    bool usable = false;
    std::string description;
    std::size_t freeBytes = 0;  // device memory free now; 0 for devices in host memory
};
DeviceInfo deviceInfo(BackendKind kind);
// The devices `--device` can name, in the order `pbf --version` lists them.
std::vector<BackendKind> deviceKinds();

// Backend-specific figures for `pbf bench` (NaN where they do not apply).
struct BackendDiagnostics {
    std::size_t memoryBytes = 0;        // particle state + solver scratch + search structures
    double neighborsPerParticle = 0.0;  // average neighbour-list length
    double compactListShare = 0.0;      // blocks with 16-bit neighbour lists, of all
};

// One process's share of a distributed run, after the last step.
struct RankFigures {
    std::uint64_t particles = 0;  // its own
    std::uint64_t ghosts = 0;     // copies of other ranks' particles next to its own
    std::uint64_t peers = 0;      // ranks it exchanged ghosts with
    std::uint64_t bytesSent = 0;  // in the step: migrants, ghosts and the ghosts' values
};

class Backend {
  public:
    virtual ~Backend() = default;
    virtual BackendKind kind() const = 0;

    virtual std::size_t size() const = 0;
    // Appends particles with the next free ids (consecutive, in order); their
    // density starts at `density`.
    virtual void append(std::span<const Vec3> positions, std::span<const Vec3> velocities,
                        float density) = 0;
    // Removes the particles whose position is in any of `outlets`; the
    // others keep their order and their ids (which are never reused).
    // Returns how many were removed (on all ranks: collective for a
    // distributed backend). Nothing happens without outlets.
    virtual std::size_t removeInside(std::span<const OutletRegion> outlets) = 0;
    // Gives the particles in each inlet buffer its velocity (the first
    // buffer that holds one; pbf/core/inlet_buffer.hpp); positions and the
    // others stay. Each rank drives its own particles.
    virtual void driveInside(std::span<const InletBuffer> buffers) = 0;
    // Advances every particle by dt seconds.
    virtual void step(const SolverContext& context, float dt) = 0;
    virtual const StageTimes& lastStageTimes() const = 0;
    // The fluid's reaction on each solid of the context during the last
    // step (one entry per solid, zero for solids that are not coupled;
    // empty when none is). Deterministic: no atomics, fixed summation order.
    virtual std::span<const SolidReaction> lastReactions() const = 0;

    // Reductions over the particles, computed where they live.
    virtual float maxSpeed() const = 0;
    // The state guard's scan (include/pbf/core/state_guard.hpp).
    virtual std::optional<BadParticle> findBadParticle(double speedLimit) const = 0;
    virtual StateStatistics statistics(const SolverContext& context) const = 0;

    // The particles in host memory, in the backend's memory order, or null
    // when they live elsewhere (then use download()).
    virtual const ParticleStore* hostState() const = 0;
    virtual ParticleStore* mutableHostState() = 0;
    // A copy of the state in memory order (the exact state: a checkpoint).
    virtual void download(ParticleStore& out) const = 0;
    // Replaces the state (a checkpoint being restored, host edits).
    virtual void upload(ParticleStore state) = 0;
    // A copy of this process's part of the state in memory order (collective
    // for a distributed backend: each rank its own, no gather), and the
    // part's first place in that order: the parts of the ranks in rank order
    // are download()'s store. One process: all of it (download(), first 0).
    virtual std::uint64_t downloadPart(ParticleStore& out) const {
        download(out);
        return 0;
    }
    // Replaces the state, each process giving its part (collective for a
    // distributed backend): `part` holds entries [first, first + part.size())
    // of a memory order of `total` particles, the parts of the processes in
    // rank order; part.nextId() is the next id of all. One process gives it
    // all (first 0, total part.size()): upload(part).
    virtual void uploadPart(ParticleStore part, std::uint64_t first, std::uint64_t total) {
        if (first != 0 || part.size() != total)
            throw std::logic_error(std::string(backendName(kind())) +
                                   " backend: one process holds all particles (a part of " +
                                   std::to_string(part.size()) + " at " + std::to_string(first) +
                                   " of " + std::to_string(total) + " was given)");
        upload(std::move(part));
    }

    virtual BackendDiagnostics diagnostics() const = 0;
    // Each process's figures, in rank order (collective there); one entry
    // (no ghosts) otherwise.
    virtual std::vector<RankFigures> rankFigures() const { return {{size(), 0, 0, 0}}; }
};

// Options that only tests and benchmarks change.
struct BackendOptions {
    // CPU backend: widest index range a block's neighbour lists may span
    // and still be stored as 16-bit offsets (NeighborSearch).
    std::uint32_t compactListSpan = 65536;
    // GPU backend: the device memory free for particles, bytes; 0: ask the
    // device (tests set it to check the refusal of scenes that do not fit).
    std::size_t deviceMemoryBytes = 0;
};

// Device memory the GPU backend needs per particle for these settings
// (with the reaction records when rigid bodies are coupled, and the sparse
// grid): a World refuses scenes that would not fit.
std::size_t deviceBytesPerParticle(const SimulationParams& params, bool rigidBodies);

// A backend of `kind` for the fixed part of `params` (domain, particle
// radius, kernel radius), holding no particles yet.
std::unique_ptr<Backend> makeBackend(BackendKind kind, const SimulationParams& params,
                                     const BackendOptions& options = {});

}  // namespace pbf
