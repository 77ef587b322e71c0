// One PBF step, Algorithm 1 of Macklin & Mueller 2013, as named stages in
// the order of the Stage list (backend/step_plan.hpp), each a member
// function below:
//   predict                  v += dt g; x* = x + dt v; the warm start; into the
//                            box, out of the solids                       (l. 1-4)
//   findNeighbors            neighbours of x*, kept for every iteration  (l. 5-7)
//   densityAndLambda         rho_i, lambda_i for all                      (l. 9-11)
//   correctPositions         dp_i for all; collisions; x* += dp          (l. 12-19)
//   recordSolveAcceleration  the warm start's a = (x* - x - dt v) / dt^2
//   updateVelocity           v = (x* - x) / dt                           (l. 21)
//   viscosityAndVorticity    XSPH viscosity; vorticity omega_i            (l. 22)
//   physicalViscosity        v += dt nu lap v (fluid.kinematic_viscosity)
//   vorticityConfinement     v += dt f_vorticity                          (l. 22)
//   surfaceTension           the surface layer's weights s, then its cohesion and
//                            adhesion, v += dt a
//   colourGradient, bandNormal, curvature, curvatureForce
//                            the curvature force: g_i, nb_i, kappa_i, then
//                            v += dt a of sigma kappa on the surface band
//   boundaryResponse         restitution and friction on the walls and
//                            solids; x = x*                               (l. 23)
// and, when a solid is coupled (a rigid body), the reaction of everything
// its boundary did to the particles (backend/reactions.hpp). The stages the
// CPU backend adds for its memory layout (sorting, reordering, packing) and
// the MPI backend's exchanges have no counterpart here.
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
    const auto stepStart = Clock::now();
    times_ = {};
    load();
    const StepTerms terms = stepTerms(context);
    const SolidSet* solids = terms.solids ? context.solids : nullptr;
    // Two-way coupling (backend/reactions.hpp): every move a coupled solid's
    // boundary gives a particle is recorded; its reaction acts on the body.
    reactions_.reset(store_.size(), solids);
    const Step s{context.params,
                 context.constants,
                 terms,
                 solids,
                 dt,
                 reactions_.active() ? &reactions_ : nullptr};

    auto t = Clock::now();
    predict(s);
    times_.predict = millisecondsSince(t);

    t = Clock::now();
    findNeighbors();
    times_.neighborSearch = times_.neighborLists = millisecondsSince(t);

    // Alg. 1 l. 8-19: Jacobi iterations, a fixed count or until the average
    // compression is small enough. Every lambda is computed from the same
    // x*, every dp from the same lambdas, then all x* move at once.
    t = Clock::now();
    const IterationControl control(s.params.solver);
    for (int corrections = 0; corrections < control.maxIterations(); ++corrections) {
        auto part = Clock::now();
        const std::int64_t compression = densityAndLambda(s);
        times_.lambda += millisecondsSince(part);
        if (control.converged(corrections, averageCompression(compression, store_.size()))) break;
        part = Clock::now();
        correctPositions(s);
        times_.deltaP += millisecondsSince(part);
        times_.iterations += 1.0;
    }
    times_.solve = millisecondsSince(t);

    t = Clock::now();
    if (terms.warmStart) recordSolveAcceleration(s);
    updateVelocity(s);
    if (terms.viscosityPass()) viscosityAndVorticity(s);
    if (terms.physicalViscosity) physicalViscosity(s);
    if (terms.vorticity) vorticityConfinement(s);
    if (terms.cohesion) surfaceTension(s);
    if (terms.curvature) {
        colourGradient(s);
        bandNormal(s);
        curvature(s);
        curvatureForce(s);
    }
    boundaryResponse(s);
    commit(terms.warmStart);
    reactions_.forces(s.c.particleMass, dt, lastReactions_);
    times_.postProcess = millisecondsSince(t);
    times_.total = millisecondsSince(stepStart);
}

// Alg. 1 l. 1-4: apply gravity, predict x*, keep it in the box; the sweep
// against the solids starts from x (no step tunnels through them). The
// warm start moves x* by the last substep's solve acceleration.
void ReferenceBackend::predict(const Step& s) {
    const Aabb& box = s.c.collisionBox;
    const float warm = s.params.solver.warmStart;
    const bool warmStart = s.terms.warmStart;
    for (std::size_t i = 0; i < position_.size(); ++i) {
        velocity_[i] += s.dt * s.params.gravity;
        predictedVelocity_[i] = velocity_[i];
        predicted_[i] = boundary::clampToBox(box, position_[i] + s.dt * velocity_[i]);
        if (warmStart)
            predicted_[i] = boundary::clampToBox(
                box, reference::warmStart(s.c, predicted_[i], solveAcceleration_[i], density_[i],
                                          warm, s.dt));
        if (s.solids) {
            const Vec3 before = predicted_[i];
            std::size_t touched = boundary::kNoSolid;
            predicted_[i] =
                boundary::resolveSolidCollision(s.c, *s.solids, position_[i], before, &touched);
            if (s.reactions) s.reactions->add(i, touched, predicted_[i], predicted_[i] - before);
        }
    }
}

// Alg. 1 l. 5-7: neighbours of x*, found once per step.
void ReferenceBackend::findNeighbors() {
    grid_.build(predicted_);
}

// Alg. 1 l. 9-11: rho_i and lambda_i at x*. Returns the sum of the
// compressions C_i in fixed point, as the CPU backend sums it (the
// iteration control's stopping test).
std::int64_t ReferenceBackend::densityAndLambda(const Step& s) {
    std::int64_t compression = 0;
    for (std::size_t i = 0; i < predicted_.size(); ++i) {
        const reference::DensityAndLambda r =
            reference::densityAndLambda(s.c, s.solids, predicted_, grid_.neighbors(i), i);
        density_[i] = r.density;
        lambda_[i] = r.lambda;
        compression += fixedPointCompression(reference::densityConstraint(s.c, r.density));
    }
    return compression;
}

// Alg. 1 l. 12-19: dp_i from the lambdas, the collision response (the box
// and the solids, l. 16-18), then every x* moves at once.
void ReferenceBackend::correctPositions(const Step& s) {
    const Aabb& box = s.c.collisionBox;
    for (std::size_t i = 0; i < predicted_.size(); ++i) {
        const Vec3 dp = reference::positionCorrection(s.c, s.solids, predicted_, lambda_,
                                                      grid_.neighbors(i), i);
        Vec3 moved = boundary::clampToBox(box, predicted_[i] + reference::overRelaxed(s.c, dp));
        if (s.solids) {
            const Vec3 unprojected = moved;
            std::size_t touched = boundary::kNoSolid;
            moved = boundary::resolveSolidCollision(s.c, *s.solids, position_[i], moved, &touched);
            if (s.reactions) {
                const reference::SolidCorrection sc =
                    reference::solidCorrection(s.c, *s.solids, lambda_[i], predicted_[i]);
                s.reactions->add(i, sc.solid, predicted_[i],
                                 reference::overRelaxed(s.c, sc.displacement));
                s.reactions->add(i, touched, moved, moved - unprojected);
            }
        }
        corrected_[i] = moved;
    }
    predicted_.swap(corrected_);
}

// The warm start's record: this substep's solve acceleration, for the next.
void ReferenceBackend::recordSolveAcceleration(const Step& s) {
    for (std::size_t i = 0; i < position_.size(); ++i)
        solveAcceleration_[i] =
            reference::solveAcceleration(position_[i], predicted_[i], predictedVelocity_[i], s.dt);
}

// Alg. 1 l. 21: the velocity the positions' change implies.
void ReferenceBackend::updateVelocity(const Step& s) {
    for (std::size_t i = 0; i < position_.size(); ++i)
        velocity_[i] = reference::velocityFromPositions(position_[i], predicted_[i], s.dt);
}

// Alg. 1 l. 22: XSPH and the vorticity omega_i both read the velocities
// above and the last iteration's densities (Jacobi). XSPH's result becomes
// v; postVelocity_ keeps the velocities it read, for the physical viscosity.
void ReferenceBackend::viscosityAndVorticity(const Step& s) {
    const FluidParams& fluid = s.params.fluid;
    const bool withVorticity = s.terms.vorticity;
    if (withVorticity) vorticity_.resize(position_.size());
    for (std::size_t i = 0; i < position_.size(); ++i) {
        const reference::NeighborIndices nbrs = grid_.neighbors(i);
        postVelocity_[i] =
            reference::xsphVelocity(s.c, fluid.viscosity, predicted_, velocity_, density_, nbrs, i);
        if (withVorticity)
            vorticity_[i] = reference::vorticity(s.c, predicted_, velocity_, density_, nbrs, i);
    }
    velocity_.swap(postVelocity_);
}

// v += dt nu lap v, the SPH Laplacian of the velocities XSPH read (Jacobi).
void ReferenceBackend::physicalViscosity(const Step& s) {
    const FluidParams& fluid = s.params.fluid;
    const std::vector<Vec3>& read = s.terms.viscosityPass() ? postVelocity_ : velocity_;
    viscosityAcceleration_.resize(position_.size());
    for (std::size_t i = 0; i < position_.size(); ++i)
        viscosityAcceleration_[i] = reference::viscosityAcceleration(
            s.c, fluid.kinematicViscosity, predicted_, read, density_, grid_.neighbors(i), i);
    for (std::size_t i = 0; i < position_.size(); ++i)
        velocity_[i] += s.dt * viscosityAcceleration_[i];
}

// Alg. 1 l. 22: vorticity confinement from the omega_i above.
void ReferenceBackend::vorticityConfinement(const Step& s) {
    for (std::size_t i = 0; i < position_.size(); ++i) {
        const Vec3 eta = reference::vorticityGradient(s.c, predicted_, vorticity_, density_,
                                                      grid_.neighbors(i), i);
        velocity_[i] += s.dt * reference::vorticityConfinement(s.c, s.params.fluid.vorticity, eta,
                                                               vorticity_[i]);
    }
}

// Surface tension's cohesion and adhesion at x*, added to the velocity like
// confinement: the force at the new positions drives the next step
// (symplectic Euler).
// The surface layer's weights s of every particle first (each reads its
// neighbours' x*, the cohesion the neighbours' s).
void ReferenceBackend::surfaceTension(const Step& s) {
    surfaceLayer_.resize(position_.size());
    for (std::size_t i = 0; i < position_.size(); ++i)
        surfaceLayer_[i] =
            reference::surfaceLayer(s.c, s.solids, predicted_, density_[i], grid_.neighbors(i), i);
    for (std::size_t i = 0; i < position_.size(); ++i) {
        const reference::SurfaceTensionAcceleration a =
            reference::surfaceTension(s.c, s.params.solver.wallAdhesion, s.solids, predicted_,
                                      surfaceLayer_, grid_.neighbors(i), i);
        velocity_[i] += s.dt * a.total;
        if (s.reactions)
            s.reactions->add(i, a.solid, predicted_[i], (s.dt * s.dt) * a.solidAcceleration);
    }
}

// The curvature force (equations.hpp), four passes: g, nb and kappa of every
// particle in turn (each reads the previous pass's field at the
// neighbours), then v += dt a after the cohesion, at x*.
void ReferenceBackend::colourGradient(const Step& s) {
    colourGradient_.resize(position_.size());
    for (std::size_t i = 0; i < position_.size(); ++i)
        colourGradient_[i] = reference::colourGradient(s.c, predicted_, grid_.neighbors(i), i);
}

void ReferenceBackend::bandNormal(const Step& s) {
    bandNormal_.resize(position_.size());
    for (std::size_t i = 0; i < position_.size(); ++i)
        bandNormal_[i] =
            reference::bandNormal(s.c, predicted_, colourGradient_, grid_.neighbors(i), i);
}

void ReferenceBackend::curvature(const Step& s) {
    curvature_.resize(position_.size());
    for (std::size_t i = 0; i < position_.size(); ++i)
        curvature_[i] = reference::curvature(s.c, predicted_, colourGradient_, bandNormal_,
                                             grid_.neighbors(i), i);
}

void ReferenceBackend::curvatureForce(const Step& s) {
    for (std::size_t i = 0; i < position_.size(); ++i)
        velocity_[i] += reference::curvatureForceVelocityChange(
            s.c, s.dt, predicted_, colourGradient_, curvature_, grid_.neighbors(i), i);
}

// Restitution and friction on the walls and solids, then x = x* (l. 23).
void ReferenceBackend::boundaryResponse(const Step& s) {
    const SolverParams& solver = s.params.solver;
    for (std::size_t i = 0; i < position_.size(); ++i) {
        Vec3 v = boundary::respondToWalls(s.c, solver.restitution, solver.friction,
                                          predicted_[i], velocity_[i]);
        if (s.solids) {
            const Vec3 before = v;
            std::size_t touched = boundary::kNoSolid;
            v = boundary::respondToSolids(*s.solids, s.c.particleRadius, solver.restitution,
                                          solver.friction, predicted_[i], v, &touched);
            if (s.reactions) s.reactions->add(i, touched, predicted_[i], (v - before) * s.dt);
        }
        velocity_[i] = v;
        position_[i] = predicted_[i];
    }
}

std::size_t ReferenceBackend::bufferBytes() const {
    std::size_t vectors = position_.capacity() + predicted_.capacity() + corrected_.capacity() +
                          velocity_.capacity() + postVelocity_.capacity() + vorticity_.capacity() +
                          predictedVelocity_.capacity() + solveAcceleration_.capacity() +
                          viscosityAcceleration_.capacity() + colourGradient_.capacity() +
                          bandNormal_.capacity();
    return sizeof(Vec3) * vectors +
           sizeof(float) * (density_.capacity() + lambda_.capacity() + curvature_.capacity() +
                            surfaceLayer_.capacity());
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
