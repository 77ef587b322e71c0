#include "backend/cpu/solver.hpp"

#include <chrono>

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
                  ReactionAccumulator* reactions) {
    const SimulationParams& params = context.params;
    const SolverConstants& c = context.constants;
    const SolidSet* solids = context.solids && !context.solids->empty() ? context.solids : nullptr;
    const FluidParams& fluid = params.fluid;
    const SolverParams& s = params.solver;
    const bool withVorticity = fluid.vorticity > 0.0f;
    const std::size_t n = p.size();
    ensureCapacity(n, withVorticity);
    const Aabb& box = c.collisionBox;
    const auto stepStart = Clock::now();

    auto t = Clock::now();
    detail::parallelFor(n, [&](std::size_t b, std::size_t e) {
        stages::predictPositions(params.gravity, dt, box, p.position, p.velocity, p.predicted, b,
                                 e);
    });
    // The last substep's pressure acceleration, in the store so that it
    // follows the particles through reorder, emitters and checkpoints;
    // dropped while the warm start is off.
    const bool warmStart = s.warmStart > 0.0f;
    p.solveAcceleration.resize(warmStart ? n : 0);
    if (warmStart) {
        detail::parallelFor(n, [&](std::size_t b, std::size_t e) {
            stages::warmStartPredictions(s.warmStart, dt, box, p.solveAcceleration, p.predicted, b,
                                         e);
        });
    }
    if (solids) {
        detail::parallelFor(n, [&](std::size_t b, std::size_t e) {
            stages::resolveSolidCollisions(c, *solids, reactions, p.position, p.predicted, b, e);
        });
    }
    times.predict = millisecondsSince(t);

    t = Clock::now();
    search_.sortByCell(p.predicted, perm_);
    times.gridBuild = millisecondsSince(t);
    auto part = Clock::now();
    p.reorder(perm_);
    times.reorder = millisecondsSince(part);
    part = Clock::now();
    search_.buildNeighborLists(p.predicted);
    times.neighborLists = millisecondsSince(part);
    times.neighborSearch = millisecondsSince(t);

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
        detail::parallelFor(n, [&](std::size_t b, std::size_t e) {
            blockCompression_[b / detail::kBlockSize] = stages::computeDensityAndLambda(
                c, solids, search_, predicted, density, withLambda, b, e);
        });
        times.lambda += millisecondsSince(part);
        // The average compression of the state the density pass just saw,
        // summed block by block in a fixed order (deterministic).
        double compression = 0.0;
        for (const double block : blockCompression_) compression += block;
        if (control.converged(corrections, n > 0 ? compression / double(n) : 0.0)) break;
        part = Clock::now();
        // Reads (x*, lambda) of the neighbours, writes the corrected x* over
        // the previous iteration's: the next density pass reads it.
        detail::parallelFor(n, [&](std::size_t b, std::size_t e) {
            stages::correctPositions(c, solids, reactions, search_, p.position, withLambda,
                                     predicted, b, e);
        });
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
    PackedPoint* velocityDensity = withLambda;
    detail::parallelFor(n, [&](std::size_t b, std::size_t e) {
        stages::updateVelocity(1.0f / dt, p.position, p.predicted, density, p.velocity,
                               velocityDensity, b, e);
    });
    if (fluid.viscosity > 0.0f || withVorticity) {
        detail::parallelFor(n, [&](std::size_t b, std::size_t e) {
            stages::applyViscosityAndComputeVorticity(
                c, fluid.viscosity, search_, predicted, velocityDensity,
                withVorticity ? &vorticity_ : nullptr, p.velocity, b, e);
        });
    }
    if (withVorticity) {
        detail::parallelFor(n, [&](std::size_t b, std::size_t e) {
            stages::applyVorticityConfinement(c, fluid.vorticity, dt, search_, p.predicted,
                                              vorticity_, density, p.velocity, b, e);
        });
    }
    detail::parallelFor(n, [&](std::size_t b, std::size_t e) {
        stages::respondToBoundaries(c, solids, s.restitution, s.friction, dt, reactions,
                                    p.predicted, p.velocity, b, e);
        stages::commitPositions(p.predicted, p.position, b, e);
    });
    times.postProcess = millisecondsSince(t);
    times.total = millisecondsSince(stepStart);
}

std::size_t Solver::memoryBytes() const {
    return search_.memoryBytes() + sizeof(std::uint32_t) * perm_.capacity() +
           sizeof(PackedPoint) * (packed_.capacity() + packedWithLambda_.capacity()) +
           sizeof(float) * 3 * vorticity_.x.capacity();
}

}  // namespace pbf
