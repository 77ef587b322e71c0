#include "backend/cpu/solver.hpp"

#include <algorithm>
#include <cstdint>

#include "backend/cpu/solver_stages.hpp"
#include "core/parallel.hpp"

namespace pbf {
namespace {

using Part = StepPlan<SolverStep>::Part;

// Runs fn(begin, end) over every particle / over the owned ones, in
// parallel blocks.
template <class Fn>
void forAll(const SolverStep& s, Fn&& fn) {
    detail::parallelFor(s.particles.size(), fn);
}
template <class Fn>
void forOwned(const SolverStep& s, Fn&& fn) {
    detail::parallelForRange(s.ownedBegin, s.ownedEnd, fn);
}

bool warmStartOn(const SolverStep& s) {
    return s.context.params.solver.warmStart > 0.0f;
}
bool vorticityOn(const SolverStep& s) {
    return s.context.params.fluid.vorticity > 0.0f;
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

void Solver::buildPlan() {
    // Alg. 1 l. 1-7: prediction, collisions, neighbours.
    plan_.add(Part::Before,
              {Stage::Predict, [](SolverStep& s) {
                   ParticleStore& p = s.particles;
                   forAll(s, [&](std::size_t b, std::size_t e) {
                       stages::predictPositions(s.context.params.gravity, s.dt,
                                                s.context.constants.collisionBox, p.position,
                                                p.velocity, p.predicted, b, e);
                   });
                   // The last substep's pressure acceleration, in the store so
                   // that it follows the particles through reorder, emitters and
                   // checkpoints; dropped while the warm start is off.
                   p.keepOptionalField(ParticleField::solveAcceleration, warmStartOn(s));
               }});
    plan_.add(Part::Before, {Stage::WarmStart,
                             [](SolverStep& s) {
                                 ParticleStore& p = s.particles;
                                 forAll(s, [&](std::size_t b, std::size_t e) {
                                     stages::warmStartPredictions(
                                         s.context.constants, s.context.params.solver.warmStart,
                                         s.dt, p.solveAcceleration, p.density.data(), p.predicted,
                                         b, e);
                                 });
                             },
                             warmStartOn});
    plan_.add(Part::Before, {Stage::CollideSolids,
                             [](SolverStep& s) {
                                 ParticleStore& p = s.particles;
                                 forAll(s, [&](std::size_t b, std::size_t e) {
                                     stages::resolveSolidCollisions(s.context.constants, *s.solids,
                                                                    s.reactions, p.position,
                                                                    p.predicted, b, e);
                                 });
                             },
                             [](const SolverStep& s) { return s.solids != nullptr; }});
    plan_.add(Part::Before, {Stage::SortByCell, [this](SolverStep& s) {
                                 const std::size_t n = s.particles.size();
                                 ensureCapacity(n, vorticityOn(s));
                                 s.ownedBegin = 0;
                                 s.ownedEnd = n;
                                 s.predicted = packed_.data();
                                 s.withLambda = packedWithLambda_.data();
                                 s.vorticity = &vorticity_;
                                 // The lambda buffer is idle until the
                                 // density pass rewrites it: the sort's scratch.
                                 search_.sortByCell(
                                     s.particles.predicted, perm_,
                                     std::as_writable_bytes(std::span(packedWithLambda_)));
                             }});
    // The position records are idle until PackPositions fills them: the
    // scratch of the 64-bit ids' permutation.
    plan_.add(Part::Before, {Stage::Reorder, [this](SolverStep& s) {
                                 s.particles.reorder(perm_,
                                                     std::as_writable_bytes(std::span(packed_)));
                             }});
    plan_.add(Part::Before, {Stage::NeighborLists, [this](SolverStep& s) {
                                 search_.buildNeighborLists(s.particles.predicted);
                             }});
    plan_.add(Part::Before,
              {Stage::PackPositions, [this](SolverStep& s) {
                   forAll(s, [&](std::size_t b, std::size_t e) {
                       stages::packPositions(s.particles.predicted, s.predicted, b, e);
                   });
                   blockCompression_.resize((s.particles.size() + detail::kBlockSize - 1) /
                                            detail::kBlockSize);
               }});

    // Alg. 1 l. 8-19: one density iteration.
    plan_.add(Part::Iteration,
              {Stage::DensityAndLambda, [this](SolverStep& s) {
                   std::fill(blockCompression_.begin(), blockCompression_.end(), std::int64_t{0});
                   forOwned(s, [&](std::size_t b, std::size_t e) {
                       blockCompression_[b / detail::kBlockSize] = stages::computeDensityAndLambda(
                           s.context.constants, s.solids, search_, s.predicted,
                           s.particles.density.data(), s.withLambda, b, e);
                   });
               }});
    // The average compression of the state the density pass just saw.
    auto errorControlled = [](const SolverStep& s) { return s.control.errorControlled(); };
    plan_.add(Part::Iteration, {Stage::CompressionTotals,
                                [this](SolverStep& s) {
                                    s.compression[0] = 0;
                                    s.compression[1] = std::int64_t(s.ownedEnd - s.ownedBegin);
                                    for (const std::int64_t block : blockCompression_)
                                        s.compression[0] += block;
                                },
                                errorControlled});
    plan_.add(Part::Iteration,
              {Stage::ConvergenceCheck,
               [](SolverStep& s) {
                   s.stopIterations = s.control.converged(
                       s.corrections,
                       averageCompression(s.compression[0], std::uint64_t(s.compression[1])));
               },
               errorControlled});
    // Reads (x*, lambda) of the neighbours, writes the corrected x* over the
    // previous iteration's: the next density pass reads it.
    plan_.add(Part::Iteration, {Stage::CorrectPositions, [this](SolverStep& s) {
                                    forOwned(s, [&](std::size_t b, std::size_t e) {
                                        stages::correctPositions(
                                            s.context.constants, s.solids, s.reactions, search_,
                                            s.particles.position, s.withLambda, s.predicted, b, e);
                                    });
                                }});

    // Alg. 1 l. 20-24: velocities, post-process, commit.
    plan_.add(Part::After, {Stage::UnpackPositions, [](SolverStep& s) {
                                forAll(s, [&](std::size_t b, std::size_t e) {
                                    stages::unpackPositions(s.predicted, s.particles.predicted, b,
                                                            e);
                                });
                            }});
    plan_.add(Part::After, {Stage::RecordSolveAcceleration,
                            [](SolverStep& s) {
                                ParticleStore& p = s.particles;
                                forAll(s, [&](std::size_t b, std::size_t e) {
                                    stages::recordSolveAcceleration(s.dt, p.position, p.predicted,
                                                                    p.velocity, p.solveAcceleration,
                                                                    b, e);
                                });
                            },
                            warmStartOn});
    // x* is still packed in `predicted`; (v, rho) go to the other buffer.
    // Ghosts included: their x, x* and density are their owners' values, so
    // (x* - x) / dt is their owners' velocity without an exchange.
    plan_.add(Part::After, {Stage::UpdateVelocity, [](SolverStep& s) {
                                ParticleStore& p = s.particles;
                                forAll(s, [&](std::size_t b, std::size_t e) {
                                    stages::updateVelocity(1.0f / s.dt, p.position, p.predicted,
                                                           p.density.data(), p.velocity,
                                                           s.withLambda, b, e);
                                });
                            }});
    plan_.add(Part::After, {Stage::ViscosityAndVorticity,
                            [this](SolverStep& s) {
                                forOwned(s, [&](std::size_t b, std::size_t e) {
                                    stages::applyViscosityAndComputeVorticity(
                                        s.context.constants, s.context.params.fluid.viscosity,
                                        search_, s.predicted, s.withLambda,
                                        vorticityOn(s) ? s.vorticity : nullptr,
                                        s.particles.velocity, b, e);
                                });
                            },
                            [](const SolverStep& s) {
                                return s.context.params.fluid.viscosity > 0.0f || vorticityOn(s);
                            }});
    // The physical viscosity (fluid.kinematic_viscosity) reads the packed
    // velocities as XSPH does (ghosts' included: UpdateVelocity ran over
    // every particle, so no exchange) and adds dt a to the velocity XSPH
    // wrote (XSPH sets v from the packed copy, so it must come first).
    plan_.add(
        Part::After,
        {Stage::PhysicalViscosity,
         [this](SolverStep& s) {
             forOwned(s, [&](std::size_t b, std::size_t e) {
                 stages::applyPhysicalViscosity(
                     s.context.constants, s.context.params.fluid.kinematicViscosity, s.dt, search_,
                     s.predicted, s.withLambda, s.particles.velocity, b, e);
             });
         },
         [](const SolverStep& s) { return s.context.params.fluid.kinematicViscosity > 0.0f; }});
    plan_.add(Part::After, {Stage::VorticityConfinement,
                            [this](SolverStep& s) {
                                forOwned(s, [&](std::size_t b, std::size_t e) {
                                    stages::applyVorticityConfinement(
                                        s.context.constants, s.context.params.fluid.vorticity, s.dt,
                                        search_, s.particles.predicted, *s.vorticity,
                                        s.particles.density.data(), s.particles.velocity, b, e);
                                });
                            },
                            vorticityOn});
    // Surface tension: cohesion of the surface layer and
    // adhesion, v += dt a at x*. Reads the neighbours' x* and density (the
    // ghosts' are current after the iterations): no exchange of its own.
    plan_.add(Part::After,
              {Stage::SurfaceTension,
               [this](SolverStep& s) {
                   const SolverConstants& c = s.context.constants;
                   PackedPoint* positionDensity = s.withLambda;  // (v, rho) is read no more
                   forAll(s, [&](std::size_t b, std::size_t e) {
                       stages::packPositionDensities(s.predicted, s.particles.density.data(),
                                                     positionDensity, b, e);
                   });
                   forOwned(s, [&](std::size_t b, std::size_t e) {
                       stages::applySurfaceTension(c, s.context.params.solver.wallAdhesion,
                                                   s.solids, s.dt, s.reactions, search_,
                                                   positionDensity, s.particles.velocity, b, e);
                   });
               },
               [](const SolverStep& s) { return s.context.constants.cohesionScale > 0.0f; }});
    // The curvature force (equations.hpp): g, nb and kappa of the owned
    // particles in turn from the neighbours' x* and previous field (the
    // ghosts' come from their owners between the passes: a ghost's own
    // neighbourhood is incomplete), then v += dt a after the cohesion.
    const auto curvatureOn = [](const SolverStep& s) {
        return s.context.constants.surfaceTension > 0.0f;
    };
    plan_.add(Part::After, {Stage::ColourGradient,
                            [this](SolverStep& s) {
                                const std::size_t n = s.particles.size();
                                colourGradient_.resize(n);
                                bandNormal_.resize(n);
                                curvature_.resize(n);
                                s.colourGradient = &colourGradient_;
                                s.bandNormal = &bandNormal_;
                                s.curvature = curvature_.data();
                                forOwned(s, [&](std::size_t b, std::size_t e) {
                                    stages::computeColourGradient(s.context.constants, search_,
                                                                  s.predicted, *s.colourGradient, b,
                                                                  e);
                                });
                            },
                            curvatureOn});
    plan_.add(Part::After, {Stage::BandNormal,
                            [this](SolverStep& s) {
                                forOwned(s, [&](std::size_t b, std::size_t e) {
                                    stages::computeBandNormal(s.context.constants, search_,
                                                              s.predicted, *s.colourGradient,
                                                              *s.bandNormal, b, e);
                                });
                            },
                            curvatureOn});
    plan_.add(Part::After, {Stage::Curvature,
                            [this](SolverStep& s) {
                                forOwned(s, [&](std::size_t b, std::size_t e) {
                                    stages::computeCurvature(s.context.constants, search_,
                                                             s.predicted, *s.colourGradient,
                                                             *s.bandNormal, s.curvature, b, e);
                                });
                            },
                            curvatureOn});
    plan_.add(Part::After, {Stage::CurvatureForce,
                            [this](SolverStep& s) {
                                forOwned(s, [&](std::size_t b, std::size_t e) {
                                    stages::applyCurvatureForce(
                                        s.context.constants, s.dt, search_, s.predicted,
                                        *s.colourGradient, s.curvature, s.particles.velocity, b, e);
                                });
                            },
                            curvatureOn});
    plan_.add(Part::After, {Stage::BoundaryResponse, [](SolverStep& s) {
                                const SolverParams& solver = s.context.params.solver;
                                ParticleStore& p = s.particles;
                                forOwned(s, [&](std::size_t b, std::size_t e) {
                                    stages::respondToBoundaries(s.context.constants, s.solids,
                                                                solver.restitution, solver.friction,
                                                                s.dt, s.reactions, p.predicted,
                                                                p.velocity, b, e);
                                    stages::commitPositions(p.predicted, p.position, b, e);
                                });
                            }});
}

void Solver::step(const SolverContext& context, ParticleStore& p, float dt, StageTimes& times,
                  ReactionAccumulator* reactions) {
    SolverStep s(context, p, dt, reactions);
    plan_.run(s, times);
}

std::size_t Solver::memoryBytes() const {
    return search_.memoryBytes() + sizeof(std::uint32_t) * perm_.capacity() +
           sizeof(PackedPoint) * (packed_.capacity() + packedWithLambda_.capacity()) +
           sizeof(float) * 3 *
               (vorticity_.x.capacity() + colourGradient_.x.capacity() + bandNormal_.x.capacity()) +
           sizeof(std::int64_t) * blockCompression_.capacity() +
           sizeof(float) * curvature_.capacity();
}

}  // namespace pbf
