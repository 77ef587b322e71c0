#include "backend/cpu/solver.hpp"

#include <algorithm>
#include <cstdint>

#include "backend/cpu/solver_stages.hpp"
#include "core/parallel.hpp"

namespace pbf {
namespace {

using Part = StepPlan<SolverStep>::Part;
using RangeStage = void (*)(const SolverStep&, std::size_t, std::size_t);

// A stage that runs a range function over every particle / over the owned
// ones, in parallel blocks.
template <RangeStage Fn>
void overAll(SolverStep& s) {
    detail::parallelFor(s.particles.size(), [&](std::size_t b, std::size_t e) { Fn(s, b, e); });
}
template <RangeStage Fn>
void overOwned(SolverStep& s) {
    detail::parallelForRange(s.ownedBegin, s.ownedEnd,
                             [&](std::size_t b, std::size_t e) { Fn(s, b, e); });
}

void predict(SolverStep& s) {
    overAll<stages::predictPositions>(s);
    // The last substep's pressure acceleration, in the store so that it
    // follows the particles through reorder, emitters and checkpoints;
    // dropped while the warm start is off.
    s.particles.keepOptionalField(ParticleField::solveAcceleration, s.terms.warmStart);
}

void convergenceCheck(SolverStep& s) {
    s.stopIterations = s.control.converged(
        s.corrections, averageCompression(s.compression[0], std::uint64_t(s.compression[1])));
}

// Surface tension reads the neighbours' (x*, s) (the ghosts' s from their
// owners): packed first, into the buffer (v, rho) was in.
void surfaceTension(SolverStep& s) {
    overAll<stages::packPositionLayers>(s);
    overOwned<stages::applySurfaceTension>(s);
}

// The wall response and x = x* in one pass over each block.
void respondAndCommit(const SolverStep& s, std::size_t begin, std::size_t end) {
    stages::respondToBoundaries(s, begin, end);
    stages::commitPositions(s, begin, end);
}

}  // namespace

Solver::Solver(const Aabb& domain, float kernelRadius, std::uint32_t compactListSpan)
    : search_(domain, kernelRadius, compactListSpan) {
    buildPlan();
}

void Solver::ensureCapacity(std::size_t n, bool withVorticity) {
    if (packed_.size() != n) {
        packed_.resize(n);
        packedWithLambda_.resize(n);
    }
    if (withVorticity) vorticity_.resize(n);  // allocates once, when first switched on
}

// The stages in Alg. 1's order: {stage, what it runs, the term that switches
// it on (none: always)}.
void Solver::buildPlan() {
    using T = StepTerms;
    const auto solver = [this](void (Solver::*stage)(SolverStep&)) {
        return [this, stage](SolverStep& s) { (this->*stage)(s); };
    };
    // Alg. 1 l. 1-7: prediction, collisions, neighbours.
    plan_.add(Part::Before, {Stage::Predict, predict});
    plan_.add(Part::Before,
              {Stage::WarmStart, overAll<stages::warmStartPredictions>, whenOn(&T::warmStart)});
    plan_.add(Part::Before,
              {Stage::CollideSolids, overAll<stages::resolveSolidCollisions>, whenOn(&T::solids)});
    plan_.add(Part::Before, {Stage::SortByCell, solver(&Solver::sortByCell)});
    // The position records are idle until PackPositions fills them: the
    // scratch of the 64-bit ids' permutation.
    plan_.add(Part::Before, {Stage::Reorder, [this](SolverStep& s) {
                                 s.particles.reorder(perm_,
                                                     std::as_writable_bytes(std::span(packed_)));
                             }});
    plan_.add(Part::Before, {Stage::NeighborLists, [this](SolverStep& s) {
                                 search_.buildNeighborLists(s.particles.predicted);
                             }});
    plan_.add(Part::Before, {Stage::PackPositions, solver(&Solver::packPositions)});

    // Alg. 1 l. 8-19: one density iteration. The tolerance's test reads the
    // average compression of the state the density pass just saw; the
    // correction reads (x*, lambda) of the neighbours and writes the
    // corrected x* over the previous iteration's: the next density pass
    // reads it.
    plan_.add(Part::Iteration, {Stage::DensityAndLambda, solver(&Solver::densityAndLambda)});
    plan_.add(Part::Iteration, {Stage::CompressionTotals, solver(&Solver::compressionTotals),
                                whenOn(&T::errorControlled)});
    plan_.add(Part::Iteration,
              {Stage::ConvergenceCheck, convergenceCheck, whenOn(&T::errorControlled)});
    plan_.add(Part::Iteration, {Stage::CorrectPositions, overOwned<stages::correctPositions>});

    // Alg. 1 l. 20-24: velocities, post-process, commit. x* is still packed
    // in `predicted`; (v, rho) go to the other buffer. Ghosts included:
    // their x, x* and density are their owners' values, so (x* - x) / dt is
    // their owners' velocity without an exchange. The physical viscosity
    // reads the packed velocities as XSPH does and adds dt a to the velocity
    // XSPH wrote (XSPH sets v from the packed copy, so it must come first).
    // The curvature force: g, nb and kappa of the owned particles in turn
    // from the neighbours' x* and previous field (the ghosts' come from
    // their owners between the passes: a ghost's own neighbourhood is
    // incomplete), then v += dt a after the cohesion.
    plan_.add(Part::After, {Stage::UnpackPositions, overAll<stages::unpackPositions>});
    plan_.add(Part::After, {Stage::RecordSolveAcceleration,
                            overAll<stages::recordSolveAcceleration>, whenOn(&T::warmStart)});
    plan_.add(Part::After, {Stage::UpdateVelocity, overAll<stages::updateVelocity>});
    plan_.add(Part::After,
              {Stage::ViscosityAndVorticity, overOwned<stages::applyViscosityAndComputeVorticity>,
               whenOn(&T::viscosityPass)});
    plan_.add(Part::After, {Stage::PhysicalViscosity, overOwned<stages::applyPhysicalViscosity>,
                            whenOn(&T::physicalViscosity)});
    plan_.add(Part::After, {Stage::VorticityConfinement,
                            overOwned<stages::applyVorticityConfinement>, whenOn(&T::vorticity)});
    plan_.add(Part::After,
              {Stage::SurfaceLayer, solver(&Solver::surfaceLayer), whenOn(&T::cohesion)});
    plan_.add(Part::After, {Stage::SurfaceTension, surfaceTension, whenOn(&T::cohesion)});
    plan_.add(Part::After,
              {Stage::ColourGradient, solver(&Solver::colourGradient), whenOn(&T::curvature)});
    plan_.add(Part::After,
              {Stage::BandNormal, overOwned<stages::computeBandNormal>, whenOn(&T::curvature)});
    plan_.add(Part::After,
              {Stage::Curvature, overOwned<stages::computeCurvature>, whenOn(&T::curvature)});
    plan_.add(Part::After, {Stage::CurvatureForce, overOwned<stages::applyCurvatureForce>,
                            whenOn(&T::curvature)});
    plan_.add(Part::After, {Stage::BoundaryResponse, overOwned<respondAndCommit>});
}

void Solver::sortByCell(SolverStep& s) {
    const std::size_t n = s.particles.size();
    ensureCapacity(n, s.terms.vorticity);
    s.ownedBegin = 0;
    s.ownedEnd = n;
    s.predicted = packed_.data();
    s.withLambda = s.velocityDensity = s.positionLayer = packedWithLambda_.data();
    s.vorticity = &vorticity_;
    // The lambda buffer is idle until the density pass rewrites it: the
    // sort's scratch.
    search_.sortByCell(s.particles.predicted, perm_,
                       std::as_writable_bytes(std::span(packedWithLambda_)));
}

void Solver::packPositions(SolverStep& s) {
    overAll<stages::packPositions>(s);
    blockCompression_.resize((s.particles.size() + detail::kBlockSize - 1) / detail::kBlockSize);
}

void Solver::densityAndLambda(SolverStep& s) {
    std::fill(blockCompression_.begin(), blockCompression_.end(), std::int64_t{0});
    detail::parallelForRange(s.ownedBegin, s.ownedEnd, [&](std::size_t b, std::size_t e) {
        blockCompression_[b / detail::kBlockSize] = stages::computeDensityAndLambda(s, b, e);
    });
}

void Solver::compressionTotals(SolverStep& s) {
    s.compression[0] = 0;
    s.compression[1] = std::int64_t(s.ownedEnd - s.ownedBegin);
    for (const std::int64_t block : blockCompression_) s.compression[0] += block;
}

void Solver::surfaceLayer(SolverStep& s) {
    surfaceLayer_.resize(s.particles.size());
    s.surfaceLayer = surfaceLayer_.data();
    overOwned<stages::computeSurfaceLayer>(s);
}

void Solver::colourGradient(SolverStep& s) {
    const std::size_t n = s.particles.size();
    colourGradient_.resize(n);
    bandNormal_.resize(n);
    curvature_.resize(n);
    s.colourGradient = &colourGradient_;
    s.bandNormal = &bandNormal_;
    s.curvature = curvature_.data();
    overOwned<stages::computeColourGradient>(s);
}

void Solver::step(const SolverContext& context, ParticleStore& p, float dt, StageTimes& times,
                  ReactionAccumulator* reactions) {
    SolverStep s(context, search_, p, dt, reactions);
    plan_.run(s, times);
}

std::size_t Solver::memoryBytes() const {
    return search_.memoryBytes() + sizeof(std::uint32_t) * perm_.capacity() +
           sizeof(PackedPoint) * (packed_.capacity() + packedWithLambda_.capacity()) +
           sizeof(float) * 3 *
               (vorticity_.x.capacity() + colourGradient_.x.capacity() + bandNormal_.x.capacity()) +
           sizeof(std::int64_t) * blockCompression_.capacity() +
           sizeof(float) * (curvature_.capacity() + surfaceLayer_.capacity());
}

}  // namespace pbf
