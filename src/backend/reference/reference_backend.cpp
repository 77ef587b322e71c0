// One PBF step, Algorithm 1 of Macklin & Mueller 2013, in the stage order of
// the CPU backend's Solver::step (backend/cpu/solver.cpp):
//   predict        v += dt g; x* = x + dt v, into the box, out of the solids (l. 1-4)
//   neighbours     lists on x*, kept for every iteration               (l. 5-7)
//   iterations     rho_i, lambda_i for all; dp_i for all; x* += dp      (l. 8-19)
//   velocity       v = (x* - x) / dt                                    (l. 21)
//   post-process   XSPH viscosity and vorticity confinement             (l. 22)
//   surface tension  cohesion and adhesion (equations.hpp), v += dt a;
//                  the continuum surface stress T_i, then its force, v += dt a
//   wall response  restitution and friction on the walls and solids
//   commit         x = x*                                               (l. 23)
// and, when a solid is coupled (a rigid body), the reaction of everything
// its boundary did to the particles (backend/reactions.hpp).
// Each stage is a loop over all particles that writes only entry i and
// reads the previous stage's arrays (Jacobi), so the result does not depend
// on the order of the particles within a loop.
#include "backend/reference/reference_backend.hpp"

#include <algorithm>
#include <chrono>
#include <limits>

#include "backend/boundary.hpp"
#include "backend/reference/equations.hpp"
#include "backend/reference/particle_sums.hpp"
#include "core/iteration_control.hpp"

namespace pbf {
namespace {

using Clock = std::chrono::steady_clock;

double millisecondsSince(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

}  // namespace

ReferenceBackend::ReferenceBackend(const SimulationParams& params)
    : grid_(params.domain, params.kernelRadius()) {}

void ReferenceBackend::load() {
    const std::size_t n = store_.size();
    position_.resize(n);
    predicted_.resize(n);
    corrected_.resize(n);
    velocity_.resize(n);
    postVelocity_.resize(n);
    density_.resize(n);
    lambda_.resize(n);
    predictedVelocity_.resize(n);
    solveAcceleration_.assign(n, Vec3{});
    const bool warm = store_.solveAcceleration.size() == n;
    for (std::size_t i = 0; i < n; ++i) {
        position_[i] = store_.position.get(i);
        velocity_[i] = store_.velocity.get(i);
        density_[i] = store_.density[i];  // the last substep's: the warm start's test
        if (warm) solveAcceleration_[i] = store_.solveAcceleration.get(i);
    }
}

void ReferenceBackend::commit(bool warmStart) {
    store_.keepOptionalField(ParticleField::solveAcceleration, warmStart);
    for (std::size_t i = 0; i < store_.size(); ++i) {
        store_.position.set(i, position_[i]);
        store_.predicted.set(i, predicted_[i]);
        store_.velocity.set(i, velocity_[i]);
        store_.density[i] = density_[i];
        if (warmStart) store_.solveAcceleration.set(i, solveAcceleration_[i]);
    }
}

void ReferenceBackend::step(const SolverContext& context, float dt) {
    const SimulationParams& params = context.params;
    const SolverConstants& c = context.constants;
    const SolidSet* solids = context.solids && !context.solids->empty() ? context.solids : nullptr;
    const Aabb& box = c.collisionBox;
    const std::size_t n = store_.size();
    const auto stepStart = Clock::now();
    times_ = {};
    load();

    // Alg. 1 l. 1-4: apply gravity, predict x*, keep it in the box; the
    // sweep against the solids starts from x (no step tunnels through them).
    // Two-way coupling (backend/reactions.hpp): every move a coupled solid's
    // boundary gives a particle is recorded; its reaction acts on the body.
    reactions_.reset(n, solids);
    ReactionAccumulator* reactions = reactions_.active() ? &reactions_ : nullptr;
    auto t = Clock::now();
    const float warm = params.solver.warmStart;
    for (std::size_t i = 0; i < n; ++i) {
        velocity_[i] += dt * params.gravity;
        predictedVelocity_[i] = velocity_[i];
        predicted_[i] = boundary::clampToBox(box, position_[i] + dt * velocity_[i]);
        if (warm > 0.0f)
            predicted_[i] = boundary::clampToBox(
                box, reference::warmStart(c, predicted_[i], solveAcceleration_[i], density_[i],
                                          warm, dt));
        if (solids) {
            const Vec3 before = predicted_[i];
            std::size_t touched = boundary::kNoSolid;
            predicted_[i] =
                boundary::resolveSolidCollision(c, *solids, position_[i], before, &touched);
            if (reactions) reactions->add(i, touched, predicted_[i], predicted_[i] - before);
        }
    }
    times_.predict = millisecondsSince(t);

    // Alg. 1 l. 5-7: neighbours of x*, found once per step.
    t = Clock::now();
    grid_.build(predicted_);
    times_.neighborSearch = times_.neighborLists = millisecondsSince(t);

    // Alg. 1 l. 8-19: Jacobi iterations. Every lambda is computed from the
    // same x*, every dp from the same lambdas, then all x* move at once.
    t = Clock::now();
    // The count: fixed, or until the average compression is small enough.
    const IterationControl control(params.solver);
    for (int corrections = 0; corrections < control.maxIterations(); ++corrections) {
        auto part = Clock::now();
        std::int64_t compression = 0;  // fixed point, as the CPU backend sums it
        for (std::size_t i = 0; i < n; ++i) {
            const reference::DensityAndLambda r =
                reference::densityAndLambda(c, solids, predicted_, grid_.neighbors(i), i);
            density_[i] = r.density;
            lambda_[i] = r.lambda;
            compression += fixedPointCompression(reference::densityConstraint(c, r.density));
        }
        times_.lambda += millisecondsSince(part);
        if (control.converged(corrections, averageCompression(compression, n))) break;
        part = Clock::now();
        for (std::size_t i = 0; i < n; ++i) {
            const Vec3 dp = reference::positionCorrection(c, solids, predicted_, lambda_,
                                                          grid_.neighbors(i), i);
            // Alg. 1 l. 16-18: collision response, the box and the solids.
            Vec3 moved = boundary::clampToBox(box, predicted_[i] + reference::overRelaxed(c, dp));
            if (solids) {
                const Vec3 unprojected = moved;
                std::size_t touched = boundary::kNoSolid;
                moved = boundary::resolveSolidCollision(c, *solids, position_[i], moved, &touched);
                if (reactions) {
                    const reference::SolidCorrection s =
                        reference::solidCorrection(c, *solids, lambda_[i], predicted_[i]);
                    reactions->add(i, s.solid, predicted_[i],
                                   reference::overRelaxed(c, s.displacement));
                    reactions->add(i, touched, moved, moved - unprojected);
                }
            }
            corrected_[i] = moved;
        }
        predicted_.swap(corrected_);
        times_.deltaP += millisecondsSince(part);
        times_.iterations += 1.0;
    }
    times_.solve = millisecondsSince(t);

    t = Clock::now();
    if (warm > 0.0f)
        for (std::size_t i = 0; i < n; ++i)
            solveAcceleration_[i] = reference::solveAcceleration(position_[i], predicted_[i],
                                                                 predictedVelocity_[i], dt);
    // Alg. 1 l. 21: the velocity the positions' change implies.
    for (std::size_t i = 0; i < n; ++i)
        velocity_[i] = reference::velocityFromPositions(position_[i], predicted_[i], dt);
    // Alg. 1 l. 22: XSPH and vorticity both read the velocities above and
    // the last iteration's densities (Jacobi); confinement adds to XSPH's result.
    const FluidParams& fluid = params.fluid;
    const bool withVorticity = fluid.vorticity > 0.0f;
    // The physical viscosity reads the same velocities as XSPH (Jacobi).
    const bool withViscosity = fluid.kinematicViscosity > 0.0f;
    if (withViscosity) {
        viscosityAcceleration_.resize(n);
        for (std::size_t i = 0; i < n; ++i)
            viscosityAcceleration_[i] =
                reference::viscosityAcceleration(c, fluid.kinematicViscosity, predicted_, velocity_,
                                                 density_, grid_.neighbors(i), i);
    }
    if (fluid.viscosity > 0.0f || withVorticity) {
        if (withVorticity) vorticity_.resize(n);
        for (std::size_t i = 0; i < n; ++i) {
            const reference::NeighborIndices nbrs = grid_.neighbors(i);
            postVelocity_[i] = reference::xsphVelocity(c, fluid.viscosity, predicted_, velocity_,
                                                       density_, nbrs, i);
            if (withVorticity)
                vorticity_[i] = reference::vorticity(c, predicted_, velocity_, density_, nbrs, i);
        }
        if (withVorticity) {
            for (std::size_t i = 0; i < n; ++i) {
                const Vec3 eta = reference::vorticityGradient(c, predicted_, vorticity_, density_,
                                                              grid_.neighbors(i), i);
                postVelocity_[i] +=
                    dt * reference::vorticityConfinement(c, fluid.vorticity, eta, vorticity_[i]);
            }
        }
        velocity_.swap(postVelocity_);
    }
    if (withViscosity)
        for (std::size_t i = 0; i < n; ++i) velocity_[i] += dt * viscosityAcceleration_[i];
    const SolverParams& s = params.solver;
    // Surface tension's cohesion and adhesion at x*, added to the
    // velocity like confinement: the force at the new positions drives the
    // next step (symplectic Euler).
    if (c.cohesionScale > 0.0f) {
        for (std::size_t i = 0; i < n; ++i) {
            const reference::SurfaceTensionAcceleration a = reference::surfaceTension(
                c, s.wallAdhesion, solids, predicted_, density_, grid_.neighbors(i), i);
            velocity_[i] += dt * a.total;
            if (reactions)
                reactions->add(i, a.solid, predicted_[i], (dt * dt) * a.solidAcceleration);
        }
    }
    // The curvature force (equations.hpp): g, nb and kappa of every
    // particle in turn, then v += dt a after the cohesion, at x*.
    if (c.surfaceTension > 0.0f) {
        colourGradient_.resize(n);
        bandNormal_.resize(n);
        curvature_.resize(n);
        for (std::size_t i = 0; i < n; ++i)
            colourGradient_[i] = reference::colourGradient(c, predicted_, grid_.neighbors(i), i);
        for (std::size_t i = 0; i < n; ++i)
            bandNormal_[i] =
                reference::bandNormal(c, predicted_, colourGradient_, grid_.neighbors(i), i);
        for (std::size_t i = 0; i < n; ++i)
            curvature_[i] = reference::curvature(c, predicted_, colourGradient_, bandNormal_,
                                                 grid_.neighbors(i), i);
        for (std::size_t i = 0; i < n; ++i)
            velocity_[i] += reference::curvatureForceVelocityChange(
                c, dt, predicted_, colourGradient_, curvature_, grid_.neighbors(i), i);
    }
    // Restitution and friction on the walls and solids, then x = x* (l. 23).
    for (std::size_t i = 0; i < n; ++i) {
        Vec3 v =
            boundary::respondToWalls(box, s.restitution, s.friction, predicted_[i], velocity_[i]);
        if (solids) {
            const Vec3 before = v;
            std::size_t touched = boundary::kNoSolid;
            v = boundary::respondToSolids(*solids, c.particleRadius, s.restitution, s.friction,
                                          predicted_[i], v, &touched);
            if (reactions) reactions->add(i, touched, predicted_[i], (v - before) * dt);
        }
        velocity_[i] = v;
        position_[i] = predicted_[i];
    }
    commit(warm > 0.0f);
    reactions_.forces(c.particleMass, dt, lastReactions_);
    times_.postProcess = millisecondsSince(t);
    times_.total = millisecondsSince(stepStart);
}

std::size_t ReferenceBackend::bufferBytes() const {
    std::size_t vectors = position_.capacity() + predicted_.capacity() + corrected_.capacity() +
                          velocity_.capacity() + postVelocity_.capacity() + vorticity_.capacity() +
                          predictedVelocity_.capacity() + solveAcceleration_.capacity() +
                          viscosityAcceleration_.capacity() + colourGradient_.capacity() +
                          bandNormal_.capacity();
    return sizeof(Vec3) * vectors +
           sizeof(float) * (density_.capacity() + lambda_.capacity() + curvature_.capacity());
}

BackendDiagnostics ReferenceBackend::diagnostics() const {
    BackendDiagnostics d;
    d.memoryBytes = store_.memoryBytes() + bufferBytes() + grid_.memoryBytes();
    d.neighborsPerParticle =
        double(grid_.totalNeighborCount()) / double(std::max<std::size_t>(1, store_.size()));
    d.compactListShare = std::numeric_limits<double>::quiet_NaN();  // no compact lists here
    return d;
}

std::unique_ptr<Backend> makeReferenceBackend(const SimulationParams& params) {
    return std::make_unique<ReferenceBackend>(params);
}

}  // namespace pbf
