#include "backend/cpu/solver.hpp"

#include <algorithm>
#include <chrono>
#include <cstdint>

#include "backend/cpu/solver_stages.hpp"
#include "core/iteration_control.hpp"
#include "core/parallel.hpp"

namespace pbf {
namespace {

using Clock = std::chrono::steady_clock;

double millisecondsSince(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

}  // namespace

Solver::Solver(const Aabb& domain, float kernelRadius, std::uint32_t compactListSpan)
    : search_(domain, kernelRadius, kMaxGridCells, compactListSpan) {}

void Solver::ensureCapacity(std::size_t n, bool withVorticity) {
    if (packed_.size() != n) {
        packed_.resize(n);
        packedWithLambda_.resize(n);
    }
    if (withVorticity) vorticity_.resize(n);  // allocates once, when first switched on
}

void Solver::step(const SolverContext& context, ParticleStore& p, float dt, StageTimes& times,
                  ReactionAccumulator* reactions, HaloExchange* halo) {
    const SimulationParams& params = context.params;
    const SolverConstants& c = context.constants;
    const SolidSet* solids = context.solids && !context.solids->empty() ? context.solids : nullptr;
    const FluidParams& fluid = params.fluid;
    const SolverParams& s = params.solver;
    const bool withVorticity = fluid.vorticity > 0.0f;
    const Aabb& box = c.collisionBox;
    const auto stepStart = Clock::now();
    times.exchange = 0.0;
    // Halo exchanges, timed apart (they are also inside the stage they serve).
    auto exchange = [&](auto&& values) {
        const auto start = Clock::now();
        halo->exchange(values);
        times.exchange += millisecondsSince(start);
    };

    auto t = Clock::now();
    detail::parallelFor(p.size(), [&](std::size_t b, std::size_t e) {
        stages::predictPositions(params.gravity, dt, box, p.position, p.velocity, p.predicted, b,
                                 e);
    });
    // The last substep's pressure acceleration, in the store so that it
    // follows the particles through reorder, emitters and checkpoints;
    // dropped while the warm start is off.
    const bool warmStart = s.warmStart > 0.0f;
    p.solveAcceleration.resize(warmStart ? p.size() : 0);
    if (warmStart) {
        detail::parallelFor(p.size(), [&](std::size_t b, std::size_t e) {
            stages::warmStartPredictions(c, s.warmStart, dt, p.solveAcceleration, p.density.data(),
                                         p.predicted, b, e);
        });
    }
    if (solids) {
        detail::parallelFor(p.size(), [&](std::size_t b, std::size_t e) {
            stages::resolveSolidCollisions(c, *solids, reactions, p.position, p.predicted, b, e);
        });
    }
    times.predict = millisecondsSince(t);

    t = Clock::now();
    if (halo) {
        halo->distribute(p);
        if (reactions) reactions->grow(p.size());
        times.exchange += millisecondsSince(t);
    }
    const std::size_t n = p.size();
    ensureCapacity(n, withVorticity);
    auto part = Clock::now();
    search_.sortByCell(p.predicted, perm_);
    times.gridBuild = millisecondsSince(part);
    part = Clock::now();
    p.reorder(perm_);
    times.reorder = millisecondsSince(part);
    part = Clock::now();
    search_.buildNeighborLists(p.predicted);
    times.neighborLists = millisecondsSince(part);
    times.neighborSearch = millisecondsSince(t);
    // The particles whose values this process computes; the rest are ghosts.
    std::size_t ownedBegin = 0, ownedEnd = n;
    if (halo) halo->ownedRange(search_, ownedBegin, ownedEnd);
    auto forOwned = [&](auto&& fn) { detail::parallelForRange(ownedBegin, ownedEnd, fn); };

    t = Clock::now();
    float* density = p.density.data();
    PackedPoint* predicted = packed_.data();
    PackedPoint* withLambda = packedWithLambda_.data();
    detail::parallelFor(n, [&](std::size_t b, std::size_t e) {
        stages::packPositions(p.predicted, predicted, b, e);
    });
    times.lambda = times.deltaP = 0.0;
    times.iterations = 0.0;
    const IterationControl control(s);
    blockCompression_.resize((n + detail::kBlockSize - 1) / detail::kBlockSize);
    for (int corrections = 0; corrections < control.maxIterations(); ++corrections) {
        part = Clock::now();
        std::fill(blockCompression_.begin(), blockCompression_.end(), std::int64_t{0});
        forOwned([&](std::size_t b, std::size_t e) {
            blockCompression_[b / detail::kBlockSize] = stages::computeDensityAndLambda(
                c, solids, search_, predicted, density, withLambda, b, e);
        });
        if (halo) {
            exchange(withLambda);
            exchange(density);
        }
        times.lambda += millisecondsSince(part);
        // The average compression of the state the density pass just saw,
        // over the owned particles of every process (exact integer sums).
        if (control.errorControlled()) {
            std::int64_t totals[2] = {0, std::int64_t(ownedEnd - ownedBegin)};
            for (const std::int64_t block : blockCompression_) totals[0] += block;
            if (halo) halo->sum(totals, 2);
            if (control.converged(corrections, averageCompression(totals[0], totals[1]))) break;
        }
        part = Clock::now();
        // Reads (x*, lambda) of the neighbours, writes the corrected x* over
        // the previous iteration's: the next density pass reads it.
        forOwned([&](std::size_t b, std::size_t e) {
            stages::correctPositions(c, solids, reactions, search_, p.position, withLambda,
                                     predicted, b, e);
        });
        if (halo) exchange(predicted);
        times.deltaP += millisecondsSince(part);
        times.iterations += 1.0;
    }
    detail::parallelFor(n, [&](std::size_t b, std::size_t e) {
        stages::unpackPositions(predicted, p.predicted, b, e);
    });
    times.solve = millisecondsSince(t);

    t = Clock::now();
    if (warmStart) {
        detail::parallelFor(n, [&](std::size_t b, std::size_t e) {
            stages::recordSolveAcceleration(dt, p.position, p.predicted, p.velocity,
                                            p.solveAcceleration, b, e);
        });
    }
    // x* is still packed in `predicted`; (v, rho) go to the other buffer.
    // Ghosts included: their x, x* and density are their owners' values, so
    // (x* - x) / dt is their owners' velocity without an exchange.
    PackedPoint* velocityDensity = withLambda;
    detail::parallelFor(n, [&](std::size_t b, std::size_t e) {
        stages::updateVelocity(1.0f / dt, p.position, p.predicted, density, p.velocity,
                               velocityDensity, b, e);
    });
    if (fluid.viscosity > 0.0f || withVorticity) {
        forOwned([&](std::size_t b, std::size_t e) {
            stages::applyViscosityAndComputeVorticity(
                c, fluid.viscosity, search_, predicted, velocityDensity,
                withVorticity ? &vorticity_ : nullptr, p.velocity, b, e);
        });
    }
    // The physical viscosity (fluid.kinematic_viscosity) reads the packed
    // velocities as XSPH does and adds dt a to the velocity XSPH wrote
    // (XSPH sets v from the packed copy, so it must come first).
    if (fluid.kinematicViscosity > 0.0f) {
        forOwned([&](std::size_t b, std::size_t e) {
            stages::applyPhysicalViscosity(c, fluid.kinematicViscosity, dt, search_, predicted,
                                           velocityDensity, p.velocity, b, e);
        });
    }
    if (withVorticity) {
        if (halo) exchange(vorticity_);
        forOwned([&](std::size_t b, std::size_t e) {
            stages::applyVorticityConfinement(c, fluid.vorticity, dt, search_, p.predicted,
                                              vorticity_, density, p.velocity, b, e);
        });
    }
    forOwned([&](std::size_t b, std::size_t e) {
        stages::respondToBoundaries(c, solids, s.restitution, s.friction, dt, reactions,
                                    p.predicted, p.velocity, b, e);
        stages::commitPositions(p.predicted, p.position, b, e);
    });
    if (halo) {
        part = Clock::now();
        halo->collect(p);
        times.exchange += millisecondsSince(part);
    }
    times.postProcess = millisecondsSince(t);
    times.total = millisecondsSince(stepStart);
}

std::size_t Solver::memoryBytes() const {
    return search_.memoryBytes() + sizeof(std::uint32_t) * perm_.capacity() +
           sizeof(PackedPoint) * (packed_.capacity() + packedWithLambda_.capacity()) +
           sizeof(float) * 3 * vorticity_.x.capacity();
}

}  // namespace pbf
