// The stages of one PBF step, each a function over the particle range
// [begin, end). Constant inputs come first, the arrays a stage writes last.
// A stage writes only the entries of its own range and reads neighbours'
// values from arrays no stage of the same pass writes (Jacobi style), which
// is what makes the step deterministic under any thread count.
#pragma once

#include <cstddef>
#include <cstdint>

#include "backend/cpu/neighbor_search.hpp"
#include "backend/cpu/solver.hpp"
#include "backend/reactions.hpp"
#include "pbf/core/particles.hpp"
#include "pbf/core/solver_constants.hpp"
#include "pbf/geometry/solids.hpp"

namespace pbf::stages {

// Alg. 1 l. 2-3: v += dt g; x* = x + dt v, projected into the collision box.
void predictPositions(const Vec3& gravity, float dt, const Aabb& box, const Float3Array& position,
                      Float3Array& velocity, Float3Array& predicted, std::size_t begin,
                      std::size_t end);

// Warm start (solver.warm_start = w): x* += w dt^2 a_i, a_i the pressure
// acceleration of the particle's last substep, for particles whose last
// density (`lastDensity`) was compressed (reference::warmStart), kept in the
// collision box.
void warmStartPredictions(const SolverConstants& c, float warm, float dt,
                          const Float3Array& solveAcceleration, const float* lastDensity,
                          Float3Array& predicted, std::size_t begin, std::size_t end);
// After the iterations: a_i = (x*_i - x_i - dt v_i) / dt^2, v_i the predicted
// velocity (reference::solveAcceleration).
void recordSolveAcceleration(float dt, const Float3Array& position, const Float3Array& predicted,
                             const Float3Array& velocity, Float3Array& solveAcceleration,
                             std::size_t begin, std::size_t end);

// x* as packed records for the iterations, and back.
void packPositions(const Float3Array& predicted, PackedPoint* packed, std::size_t begin,
                   std::size_t end);
void unpackPositions(const PackedPoint* packed, Float3Array& predicted, std::size_t begin,
                     std::size_t end);

// Paper eq. 1-2 and 11: density rho_i (poly6) and the Lagrange multiplier
// lambda_i = -C_i / (sum_k |grad_k C_i|^2 + eps), with C_i = max(rho_i/rho0 - 1, 0)
// so that particles at a free surface (missing neighbours) are never pulled in.
// Writes x*_i with lambda_i in w to `withLambda` (the next pass reads both).
// Returns the sum of C_i over the range (for the iteration control).
std::int64_t computeDensityAndLambda(const SolverConstants& c, const SolidSet* solids,
                                     const NeighborSearch& search, const PackedPoint* predicted,
                                     float* density, PackedPoint* withLambda, std::size_t begin,
                                     std::size_t end);

// Paper eq. 12-14: dp_i = 1/rho0 sum_j (lambda_i + lambda_j + s_corr) m grad W_ij,
// then x*_i + dp_i projected into the collision box and out of the solids
// (Alg. 1 l. 16-18), dp scaled by the over-relaxation omega, written to
// `corrected` (Jacobi: neighbours read
// `withLambda`). `start` (x at the start of the step) is where the sweep
// against solids begins. With `reactions` (may be null) the moves that the
// coupled solids' boundary terms and projections give each particle are
// recorded (backend/reactions.hpp); [begin, end) must then lie in one block of
// detail::kBlockSize.
void correctPositions(const SolverConstants& c, const SolidSet* solids,
                      ReactionAccumulator* reactions, const NeighborSearch& search,
                      const Float3Array& start, const PackedPoint* withLambda,
                      PackedPoint* corrected, std::size_t begin, std::size_t end);

// boundary::resolveSolidCollision for every particle of the range (x -> x*),
// recording coupled solids' pushes in `reactions` (may be null).
void resolveSolidCollisions(const SolverConstants& c, const SolidSet& solids,
                            ReactionAccumulator* reactions, const Float3Array& position,
                            Float3Array& predicted, std::size_t begin, std::size_t end);

// Alg. 1 l. 21: v = (x* - x) / dt; also packs (v, rho) for the next pass.
void updateVelocity(float inverseDt, const Float3Array& position, const Float3Array& predicted,
                    const float* density, Float3Array& velocity, PackedPoint* velocityDensity,
                    std::size_t begin, std::size_t end);

// XSPH: v_i += c sum_j 2m/(rho_i + rho_j) (v_j - v_i) W_ij (eq. 17, with the
// symmetric volume so that momentum is conserved), reading v_j and rho_j
// from `velocityDensity`. With `vorticity` (may be null) also the curl
// omega_i = sum_j V_j grad_i W_ij x (v_j - v_i) (paper eq. 15).
void applyViscosityAndComputeVorticity(const SolverConstants& c, float viscosity,
                                       const NeighborSearch& search, const PackedPoint* predicted,
                                       const PackedPoint* velocityDensity, Float3Array* vorticity,
                                       Float3Array& velocity, std::size_t begin, std::size_t end);

// Physical viscosity: v_i += dt nu lap v_i (reference::viscosityTerm, the
// SPH Laplacian with the domain walls as free-slip mirrors), reading x_j
// from `predicted` and (v_j, rho_j) from `velocityDensity` (Jacobi: the
// velocities before XSPH, as XSPH reads them).
void applyPhysicalViscosity(const SolverConstants& c, float nu, float dt,
                            const NeighborSearch& search, const PackedPoint* predicted,
                            const PackedPoint* velocityDensity, Float3Array& velocity,
                            std::size_t begin, std::size_t end);

// Vorticity confinement (eq. 16): N = eta/|eta|, eta = grad |omega|, and
// a_i = epsilon h |omega_i| (N x omega_i); adds dt a_i to v_i.
void applyVorticityConfinement(const SolverConstants& c, float vorticityEpsilon, float dt,
                               const NeighborSearch& search, const Float3Array& predicted,
                               const Float3Array& vorticity, const float* density,
                               Float3Array& velocity, std::size_t begin, std::size_t end);

// Surface tension (reference::onSurface, cohesionTerm, adhesionAcceleration):
// v_i += dt a_i, a_i the cohesion of the surface layer from the neighbours'
// (x*, rho) in `positionDensity` plus the pull of the walls (`wallAdhesion`)
// and of the nearest solid (its SolidSet::adhesion). A coupled solid's pull
// is recorded in `reactions` (may be null) as the move dt^2 a; [begin, end)
// must then lie in one block of detail::kBlockSize.
void applySurfaceTension(const SolverConstants& c, float wallAdhesion, const SolidSet* solids,
                         float dt, ReactionAccumulator* reactions, const NeighborSearch& search,
                         const PackedPoint* positionDensity, Float3Array& velocity,
                         std::size_t begin, std::size_t end);

// The curvature force (curvature_pass.cpp; reference::colourGradientOf,
// bandNormalOf, curvatureOf, curvatureForceVelocityChangeOf), one pass per
// field, each reading the previous field at the neighbours (all of them
// computed first): g_i, the band's averaged normals nb_i, kappa_i, then
// v_i += dt a_i.
void computeColourGradient(const SolverConstants& c, const NeighborSearch& search,
                           const PackedPoint* predicted, Float3Array& gradient, std::size_t begin,
                           std::size_t end);
void computeBandNormal(const SolverConstants& c, const NeighborSearch& search,
                       const PackedPoint* predicted, const Float3Array& gradient,
                       Float3Array& normal, std::size_t begin, std::size_t end);
void computeCurvature(const SolverConstants& c, const NeighborSearch& search,
                      const PackedPoint* predicted, const Float3Array& gradient,
                      const Float3Array& normal, float* curvature, std::size_t begin,
                      std::size_t end);
void applyCurvatureForce(const SolverConstants& c, float dt, const NeighborSearch& search,
                         const PackedPoint* predicted, const Float3Array& gradient,
                         const float* curvature, Float3Array& velocity, std::size_t begin,
                         std::size_t end);

// (x*, rho) packed for surface tension's pass.
void packPositionDensities(const PackedPoint* predicted, const float* density,
                           PackedPoint* positionDensity, std::size_t begin, std::size_t end);

// Restitution and friction against the walls of the collision box and the
// solids (boundary::respondToWalls, boundary::respondToSolids; `solids` may
// be null). A coupled solid's velocity change dv is recorded in `reactions`
// (may be null) as the move dv dt.
void respondToBoundaries(const SolverConstants& c, const SolidSet* solids, float restitution,
                         float friction, float dt, ReactionAccumulator* reactions,
                         const Float3Array& predicted, Float3Array& velocity, std::size_t begin,
                         std::size_t end);

// Alg. 1 l. 23: x = x*.
void commitPositions(const Float3Array& predicted, Float3Array& position, std::size_t begin,
                     std::size_t end);

}  // namespace pbf::stages
