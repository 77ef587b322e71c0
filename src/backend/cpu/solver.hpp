// The CPU backend's solver: Position Based Fluids (Macklin & Mueller 2013,
// Algorithm 1) with SIMD neighbour passes (private header).
//
// One call of Solver::step advances the particles by dt by running the
// solver's plan (backend/step_plan.hpp; the stages in order in buildPlan):
//   predict        v += dt g;  x* = x + dt v                  (Alg. 1, l. 1-4)
//   neighbours     sort by grid cell, reorder, neighbour lists (l. 5-7)
//   iterations     rho_i, lambda_i; dp_i with s_corr; x* += dp; box projection (l. 8-19)
//   velocity       v = (x* - x) / dt                           (l. 21)
//   post-process   vorticity confinement, XSPH viscosity       (l. 22)
//   surface tension cohesion of the surface layer, adhesion: v += dt a;
//                  the curvature force: g_i, the band's normals nb_i, kappa_i,
//                  then v += dt a of sigma kappa on the surface band
//   wall response  restitution and friction on the domain walls
//   commit         x = x*                                      (l. 23)
// Every stage is a function over particle ranges in solver_stages.hpp; the
// scalar equations they implement are in backend/reference/equations.hpp.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "backend/cpu/neighbor_search.hpp"
#include "backend/reactions.hpp"
#include "backend/step_plan.hpp"
#include "backend/step_terms.hpp"
#include "core/iteration_control.hpp"
#include "pbf/backend/backend.hpp"
#include "pbf/core/particles.hpp"

namespace pbf {

// Four floats of one particle (x* and lambda, or v and rho), 16-byte aligned
// so that the SIMD neighbour loops load a neighbour's record whole.
struct alignas(16) PackedPoint {
    float x = 0.0f, y = 0.0f, z = 0.0f, w = 0.0f;
};

// The per-step context of the CPU solver's stages (solver_stages.hpp: each
// stage is a function of this context and a range of particles): the
// step's constant inputs and the terms they switch on, the particles, the
// neighbour search, and the solver's scratch the stages pass between them
// (and a wrapping backend's stages read: the MPI backend's exchanges).
struct SolverStep : StepProgress {
    SolverStep(const SolverContext& stepContext, const NeighborSearch& stepSearch,
               ParticleStore& store, float stepDt, ReactionAccumulator* stepReactions)
        : context(stepContext),
          terms(stepTerms(stepContext)),
          solids(terms.solids ? stepContext.solids : nullptr),
          search(stepSearch),
          particles(store),
          dt(stepDt),
          reactions(stepReactions),
          control(stepContext.params.solver) {
        maxIterations = control.maxIterations();
    }

    const SolverContext& context;
    StepTerms terms;         // the optional terms this step runs
    const SolidSet* solids;  // null when there are none
    const NeighborSearch& search;
    ParticleStore& particles;
    float dt;
    ReactionAccumulator* reactions;  // null when no solid is coupled
    IterationControl control;
    // The particles whose values this process computes, [ownedBegin,
    // ownedEnd) of the sorted store; the rest are ghosts (MPI). All of them
    // in one process.
    std::size_t ownedBegin = 0, ownedEnd = 0;
    // Sum of C_i over the owned particles (fixed point) and their count:
    // the tolerance's stopping test (core/iteration_control.hpp).
    std::int64_t compression[2] = {0, 0};
    // The iterations alternate between these (Jacobi): x* -> (x*, lambda) ->
    // corrected x*. The post-process reuses them: x* stays in `predicted`,
    // the other buffer holds (v, rho) from the velocity update on, then
    // (x*, s) for surface tension (the three names are the one buffer).
    PackedPoint* predicted = nullptr;
    PackedPoint* withLambda = nullptr;
    PackedPoint* velocityDensity = nullptr;
    PackedPoint* positionLayer = nullptr;
    Float3Array* vorticity = nullptr;  // omega_i, only while vorticity confinement is on
    float* surfaceLayer = nullptr;     // s_i, only while surface tension is on
    // The curvature force's fields, only while surface tension is on.
    Float3Array* colourGradient = nullptr;  // g_i
    Float3Array* bandNormal = nullptr;      // nb_i
    float* curvature = nullptr;             // kappa_i
};

class Solver {
  public:
    // A grid over `domain` with cells of the kernel radius.
    // `compactListSpan` (tests only): see NeighborSearch.
    Solver(const Aabb& domain, float kernelRadius, std::uint32_t compactListSpan = 65536);
    // The plan's stages refer to this solver.
    Solver(const Solver&) = delete;
    Solver& operator=(const Solver&) = delete;

    // Advances the particles by dt seconds; stage times go to `times`. With
    // `reactions` (reset for this step; null when no solid is coupled) the
    // coupled solids' boundary moves are recorded (backend/reactions.hpp).
    void step(const SolverContext& context, ParticleStore& particles, float dt, StageTimes& times,
              ReactionAccumulator* reactions = nullptr);

    // The stages of a step, in order; a wrapping backend inserts its own.
    StepPlan<SolverStep>& plan() { return plan_; }
    const StepPlan<SolverStep>& plan() const { return plan_; }

    const NeighborSearch& neighborSearch() const { return search_; }
    // Solver-owned memory in bytes (scratch arrays, grid, neighbour lists).
    std::size_t memoryBytes() const;

  private:
    void buildPlan();
    void ensureCapacity(std::size_t n, bool withVorticity);
    // The stages that use the solver's scratch (the others are
    // solver_stages.hpp's functions as they are).
    void sortByCell(SolverStep& s);
    void packPositions(SolverStep& s);
    void densityAndLambda(SolverStep& s);
    void compressionTotals(SolverStep& s);
    void surfaceLayer(SolverStep& s);
    void colourGradient(SolverStep& s);

    NeighborSearch search_;
    StepPlan<SolverStep> plan_;

    // Scratch owned by the solver: sized once per particle count, reused every step.
    std::vector<std::uint32_t> perm_;
    std::vector<PackedPoint> packed_;
    std::vector<PackedPoint> packedWithLambda_;
    Float3Array vorticity_;
    std::vector<std::int64_t> blockCompression_;  // sum of C_i per block, fixed point
    std::vector<float> surfaceLayer_;             // s_i, the surface layer's weights
    Float3Array colourGradient_;                  // the curvature force's g_i
    Float3Array bandNormal_;                      // nb_i
    std::vector<float> curvature_;                // kappa_i
};

}  // namespace pbf
