// The CPU backend's solver: Position Based Fluids (Macklin & Mueller 2013,
// Algorithm 1) with SIMD neighbour passes (private header).
//
// One call of Solver::step advances the particles by dt:
//   predict        v += dt g;  x* = x + dt v                  (Alg. 1, l. 1-4)
//   neighbours     sort by grid cell, reorder, neighbour lists (l. 5-7)
//   iterations     rho_i, lambda_i; dp_i with s_corr; x* += dp; box projection (l. 8-19)
//   velocity       v = (x* - x) / dt                           (l. 21)
//   post-process   vorticity confinement, XSPH viscosity       (l. 22)
//   wall response  restitution and friction on the domain walls
//   commit         x = x*                                      (l. 23)
// Every stage is a function over particle ranges in solver_stages.hpp; the
// scalar equations they implement are in backend/reference/equations.hpp.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "backend/cpu/neighbor_search.hpp"
#include "core/reactions.hpp"
#include "pbf/backend.hpp"
#include "pbf/particles.hpp"

namespace pbf {

// Four floats of one particle (x* and lambda, or v and rho), 16-byte aligned
// so that the SIMD neighbour loops load a neighbour's record whole.
struct alignas(16) PackedPoint {
    float x = 0.0f, y = 0.0f, z = 0.0f, w = 0.0f;
};

// The part of a step that crosses process boundaries (backend/mpi): a
// distributed backend hands one to Solver::step, which calls it where
// particles owned by other processes must be present and current. Between
// steps the store holds only the particles this process owns; during a step
// it also holds copies (ghosts) of the others' particles within one kernel
// radius, and the passes that write per-particle values run on the owned
// ones only.
class HaloExchange {
  public:
    virtual ~HaloExchange() = default;
    // After prediction and the swept collision: particles whose x* left this
    // process's part go to their owners, arrivals and ghosts are added, and
    // the store is put into the order the one-process solver would have
    // them in (so that the stable sort gives the same relative order).
    virtual void distribute(ParticleStore& p) = 0;
    // After the sort: the owned particles are [begin, end) of the store.
    virtual void ownedRange(const NeighborSearch& search, std::size_t& begin, std::size_t& end) = 0;
    // The ghosts' entries of these arrays (store order) from their owners.
    virtual void exchange(PackedPoint* records) = 0;  // x* and the fourth float (lambda)
    virtual void exchange(float* values) = 0;         // density
    virtual void exchange(Float3Array& values) = 0;   // vorticity
    // Sums over all processes, in place (integers: exact in any order).
    virtual void sum(std::int64_t* values, int count) = 0;
    // End of the step: drops the ghosts.
    virtual void collect(ParticleStore& p) = 0;
};

class Solver {
  public:
    // A grid over `domain` with cells of the kernel radius.
    // `compactListSpan` (tests only): see NeighborSearch.
    Solver(const Aabb& domain, float kernelRadius, std::uint32_t compactListSpan = 65536);

    // Advances the particles by dt seconds; stage times go to `times`. With
    // `reactions` (reset for this step; null when no solid is coupled) the
    // coupled solids' boundary moves are recorded (core/reactions.hpp).
    // With `halo` the step is one process's share of a distributed step.
    void step(const SolverContext& context, ParticleStore& particles, float dt, StageTimes& times,
              ReactionAccumulator* reactions = nullptr, HaloExchange* halo = nullptr);

    const NeighborSearch& neighborSearch() const { return search_; }
    // Solver-owned memory in bytes (scratch arrays, grid, neighbour lists).
    std::size_t memoryBytes() const;

  private:
    void ensureCapacity(std::size_t n, bool withVorticity);

    NeighborSearch search_;

    // Scratch owned by the solver: sized once per particle count, reused every step.
    std::vector<std::uint32_t> perm_;
    // The iterations alternate between these (Jacobi): x* -> (x*, lambda) ->
    // corrected x*. The post-process reuses them for x* and (v, rho).
    std::vector<PackedPoint> packed_;
    std::vector<PackedPoint> packedWithLambda_;
    Float3Array vorticity_;  // omega_i, only while vorticity confinement is on
    std::vector<std::int64_t> blockCompression_;  // sum of C_i per block, fixed point (iteration control)
};

}  // namespace pbf
