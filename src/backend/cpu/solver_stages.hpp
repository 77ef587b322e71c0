// The stages of one PBF step, each a function of the step's context
// (SolverStep, solver.hpp) and a particle range [begin, end): the context
// gives the constant inputs, the terms that are on and the arrays; a stage
// takes what it reads and writes into locals before its loop. A stage
// writes only the entries of its own range and reads neighbours' values
// from arrays no stage of the same pass writes (Jacobi style), which is
// what makes the step deterministic under any thread count.
#pragma once

#include <cstddef>
#include <cstdint>

#include "backend/cpu/solver.hpp"

namespace pbf::stages {

// Alg. 1 l. 2-3: v += dt g; x* = x + dt v, projected into the collision box.
void predictPositions(const SolverStep& s, std::size_t begin, std::size_t end);

// Warm start (solver.warm_start = w): x* += w dt^2 a_i, a_i the pressure
// acceleration of the particle's last substep (particles.solveAcceleration),
// for particles whose last density was compressed (reference::warmStart),
// kept in the collision box.
void warmStartPredictions(const SolverStep& s, std::size_t begin, std::size_t end);
// After the iterations: a_i = (x*_i - x_i - dt v_i) / dt^2, v_i the predicted
// velocity (reference::solveAcceleration).
void recordSolveAcceleration(const SolverStep& s, std::size_t begin, std::size_t end);

// x* (particles.predicted) as packed records for the iterations
// (s.predicted), and back.
void packPositions(const SolverStep& s, std::size_t begin, std::size_t end);
void unpackPositions(const SolverStep& s, std::size_t begin, std::size_t end);

// Paper eq. 1-2 and 11: density rho_i (poly6) and the Lagrange multiplier
// lambda_i = -C_i / (sum_k |grad_k C_i|^2 + eps), with C_i = max(rho_i/rho0 - 1, 0)
// so that particles at a free surface (missing neighbours) are never pulled in.
// Reads x* from s.predicted, writes rho_i to particles.density and x*_i with
// lambda_i in w to s.withLambda (the next pass reads both). Returns the sum
// of C_i over the range (for the iteration control).
std::int64_t computeDensityAndLambda(const SolverStep& s, std::size_t begin, std::size_t end);

// Paper eq. 12-14: dp_i = 1/rho0 sum_j (lambda_i + lambda_j + s_corr) m grad W_ij,
// then x*_i + dp_i projected into the collision box and out of the solids
// (Alg. 1 l. 16-18), dp scaled by the over-relaxation omega, written to
// s.predicted (Jacobi: neighbours read s.withLambda). x at the start of
// the step (particles.position) is where the sweep against solids begins.
// With s.reactions the moves that the coupled solids' boundary terms and
// projections give each particle are recorded (backend/reactions.hpp);
// [begin, end) must then lie in one block of detail::kBlockSize.
void correctPositions(const SolverStep& s, std::size_t begin, std::size_t end);

// boundary::resolveSolidCollision for every particle of the range (x -> x*),
// recording coupled solids' pushes in s.reactions (may be null). Solids only.
void resolveSolidCollisions(const SolverStep& s, std::size_t begin, std::size_t end);

// Alg. 1 l. 21: v = (x* - x) / dt; also packs (v, rho) into
// s.velocityDensity for the next passes.
void updateVelocity(const SolverStep& s, std::size_t begin, std::size_t end);

// XSPH: v_i += c sum_j 2m/(rho_i + rho_j) (v_j - v_i) W_ij (eq. 17, with the
// symmetric volume so that momentum is conserved), reading v_j and rho_j
// from s.velocityDensity. With the vorticity term on also the curl
// omega_i = sum_j V_j grad_i W_ij x (v_j - v_i) (paper eq. 15) into s.vorticity.
void applyViscosityAndComputeVorticity(const SolverStep& s, std::size_t begin, std::size_t end);

// Physical viscosity: v_i += dt nu lap v_i (reference::viscosityTerm, the
// SPH Laplacian with the domain walls as free-slip mirrors), reading x_j
// from s.predicted and (v_j, rho_j) from s.velocityDensity (Jacobi: the
// velocities before XSPH, as XSPH reads them).
void applyPhysicalViscosity(const SolverStep& s, std::size_t begin, std::size_t end);

// Vorticity confinement (eq. 16): N = eta/|eta|, eta = grad |omega|, and
// a_i = epsilon h |omega_i| (N x omega_i); adds dt a_i to v_i.
void applyVorticityConfinement(const SolverStep& s, std::size_t begin, std::size_t end);

// s_i, the surface layer's weight (reference::surfaceLayerOf: on the surface
// and not a strand below the resolution), from the neighbours' x* in
// s.predicted and the particle's density, into s.surfaceLayer.
void computeSurfaceLayer(const SolverStep& s, std::size_t begin, std::size_t end);

// Surface tension (reference::cohesionTerm, adhesionAcceleration):
// v_i += dt a_i, a_i the cohesion of the surface layer from the neighbours'
// (x*, s) in s.positionLayer plus the pull of the walls
// (solver.wall_adhesion) and of the nearest solid (its SolidSet::adhesion).
// A coupled solid's pull is recorded in s.reactions (may be null) as the
// move dt^2 a; [begin, end) must then lie in one block of detail::kBlockSize.
void applySurfaceTension(const SolverStep& s, std::size_t begin, std::size_t end);

// The curvature force (curvature_pass.cpp; reference::colourGradientOf,
// bandNormalOf, curvatureOf, curvatureForceVelocityChangeOf), one pass per
// field, each reading the previous field at the neighbours (all of them
// computed first): g_i, the band's averaged normals nb_i, kappa_i, then
// v_i += dt a_i.
void computeColourGradient(const SolverStep& s, std::size_t begin, std::size_t end);
void computeBandNormal(const SolverStep& s, std::size_t begin, std::size_t end);
void computeCurvature(const SolverStep& s, std::size_t begin, std::size_t end);
void applyCurvatureForce(const SolverStep& s, std::size_t begin, std::size_t end);

// (x*, s) packed into s.positionLayer for surface tension's pass.
void packPositionLayers(const SolverStep& s, std::size_t begin, std::size_t end);

// Restitution and friction against the walls of the collision box and the
// solids (boundary::respondToWalls, boundary::respondToSolids). A coupled
// solid's velocity change dv is recorded in s.reactions (may be null) as the
// move dv dt.
void respondToBoundaries(const SolverStep& s, std::size_t begin, std::size_t end);

// Alg. 1 l. 23: x = x*.
void commitPositions(const SolverStep& s, std::size_t begin, std::size_t end);

}  // namespace pbf::stages
