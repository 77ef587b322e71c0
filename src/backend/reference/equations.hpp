// The equations of Position Based Fluids (Macklin & Mueller 2013, "Position
// Based Fluids", ACM TOG 32(4)), one short scalar function each, written to
// be read beside the paper (private header).
//
// These are the oracle the fast paths are tested against (STYLE.md, item 13):
// the SIMD passes of backend/cpu/neighbor_passes.cpp compute the same
// quantities with other summation orders. Plain floats, pbf::Vec3 and
// SolverConstants only, and PBF_HD, so that a CUDA kernel can call them too.
//
// Conventions:
//   rij = x_i - x_j; grad W_ij is the gradient of W(rij) with respect to x_i.
//   Mass-weighted SPH: every particle has mass m = c.particleMass, so the
//   paper's 1/rho0 grad W becomes m/rho0 grad W (the constraint is
//   C_i = rho_i/rho0 - 1 with rho_i a mass density).
//   The kernels return 0 outside their support (r >= h): a pair that moved
//   apart since the neighbour search adds nothing.
//   The walls and solids (backend/boundary.hpp) act as the rest lattice
//   continued beyond their surface: they add a kernel sum (1/m^3) to the
//   density and its gradient (1/m^4) to grad_i C_i, and carry no lambda.
#pragma once

#include "pbf/core/config.hpp"
#include "pbf/core/solver_constants.hpp"
#include "pbf/core/vec3.hpp"

namespace pbf::reference {

// m / rho0, the factor between grad W and grad C (eq. 8 with masses).
PBF_HD inline float massOverRestDensity(const SolverConstants& c) {
    return c.particleMass * c.inverseRestDensity;
}

// ---- Density and the density constraint (sec. 3) ---------------------------

// Eq. 2, the term of neighbour j: m W_poly6(|x_i - x_j|).
PBF_HD inline float densityTerm(const SolverConstants& c, const Vec3& rij) {
    return c.particleMass * c.poly6.value(lengthSquared(rij));
}

// Eq. 2, the term j = i: a particle counts towards its own density.
PBF_HD inline float selfDensity(const SolverConstants& c) {
    return c.particleMass * c.poly6.value(0.0f);
}

// The walls' and solids' share of eq. 2: their kernel sum over a lattice of
// particles of mass m.
PBF_HD inline float boundaryDensity(const SolverConstants& c, float boundaryKernelSum) {
    return c.particleMass * boundaryKernelSum;
}

// Eq. 1, C_i = rho_i / rho0 - 1, clamped at 0: a particle with missing
// neighbours (free surface) is under-dense and must not be pulled inward,
// so only compression is corrected (the unilateral constraint of sec. 3).
PBF_HD inline float densityConstraint(const SolverConstants& c, float density) {
    const float constraint = density * c.inverseRestDensity - 1.0f;
    return constraint > 0.0f ? constraint : 0.0f;
}

// ---- Constraint gradients and lambda (eq. 8-11) -----------------------------

// Eq. 8, k = j: grad_{x_j} C_i = -(m/rho0) grad W_ij.
PBF_HD inline Vec3 constraintGradientOfNeighbor(const SolverConstants& c, const Vec3& rij) {
    return -(massOverRestDensity(c) * c.spiky.gradient(rij, length(rij)));
}

// Eq. 8, k = i: grad_{x_i} C_i = (m/rho0) sum_j grad W_ij; this is the
// term of neighbour j.
PBF_HD inline Vec3 constraintGradientOfSelfTerm(const SolverConstants& c, const Vec3& rij) {
    return massOverRestDensity(c) * c.spiky.gradient(rij, length(rij));
}

// The walls' and solids' share of grad_{x_i} C_i: (m/rho0) times the
// gradient of their kernel sum.
PBF_HD inline Vec3 boundaryConstraintGradient(const SolverConstants& c,
                                              const Vec3& boundaryGradient) {
    return massOverRestDensity(c) * boundaryGradient;
}

// Eq. 11: lambda_i = -C_i / (sum_k |grad_k C_i|^2 + eps), with the
// constraint-force-mixing relaxation eps in SI units (SolverConstants).
// `gradientSquaredSum` = |grad_i C_i|^2 + sum_j |grad_j C_i|^2 (eq. 9-10).
PBF_HD inline float lambda(const SolverConstants& c, float constraint, float gradientSquaredSum) {
    return -constraint / (gradientSquaredSum + c.relaxationEpsilon);
}

// ---- Position correction (eq. 12-14) ----------------------------------------

// Eq. 13, artificial pressure s_corr = -k (W(r) / W(dq h))^n; the sign and
// the units of k are in c.scorrScale (SolverConstants: units trap).
PBF_HD inline float artificialPressure(const SolverConstants& c, const Vec3& rij) {
    const float ratio = c.poly6.value(lengthSquared(rij)) * c.scorrInverseWdq;
    float power = 1.0f;
    for (int k = 0; k < c.scorrExponent; ++k) power *= ratio;
    return c.scorrScale * power;
}

// Eq. 14, the term of neighbour j: (m/rho0) (lambda_i + lambda_j + s_corr) grad W_ij.
PBF_HD inline Vec3 positionCorrectionTerm(const SolverConstants& c, float lambdaI, float lambdaJ,
                                          const Vec3& rij) {
    const float weight = lambdaI + lambdaJ + artificialPressure(c, rij);
    return (massOverRestDensity(c) * weight) * c.spiky.gradient(rij, length(rij));
}

// The walls' and solids' share of eq. 14: they carry no lambda of their own,
// so only lambda_i times their part of grad_i C_i.
PBF_HD inline Vec3 boundaryPositionCorrection(const SolverConstants& c, float lambdaI,
                                              const Vec3& boundaryGradient) {
    return (lambdaI * massOverRestDensity(c)) * boundaryGradient;
}

// ---- Warm start -------------------------------------------------------------
//
// A substep's Jacobi iterations start from x* = x + dt v + dt^2 g and must
// push back, layer by layer, the compression gravity put into a column
// (Jacobi propagates a correction about one kernel radius per iteration).
// The previous substep found that push: its total correction per dt^2 is
// the pressure acceleration a_i. Starting the iterations from the
// prediction plus a fraction w of it (w dt^2 a_i) leaves them only the
// change — the warm start of DFSPH's pressure solvers (Bender & Koschier
// 2017, sec. 4) and of impulse solvers (Box2D). w = 1 repeats the last push
// in full and feeds back on itself in violent flows (measured on the dam
// break: 17 % more substeps, 14 % more kinetic energy at the impact; 0.8
// does neither); see docs/performance.md.

// The warm-started prediction x* + w dt^2 a, for a particle that ended its
// last substep compressed (density constraint active, C_i > 0) only: as
// DFSPH warm-starts only particles whose density exceeds the rest density.
// A particle the last push has already separated (a splash leaving the wall)
// would be pushed again by a stale acceleration, and the unilateral
// constraint never pulls it back: the dam break's tolerance runs blew up at
// the impact without this test (61 m/s at frame 14, warm 0.4, omega 1.2).
PBF_HD inline Vec3 warmStart(const SolverConstants& c, const Vec3& predicted,
                             const Vec3& acceleration, float lastDensity, float warm, float dt) {
    if (!(densityConstraint(c, lastDensity) > 0.0f)) return predicted;
    return predicted + acceleration * (warm * dt * dt);
}

// a = (x*_final - x - dt v) / dt^2, v the velocity after gravity (before the
// iterations): everything the solve (warm start included) moved the particle.
PBF_HD inline Vec3 solveAcceleration(const Vec3& position, const Vec3& corrected,
                                     const Vec3& predictedVelocity, float dt) {
    return (corrected - position - predictedVelocity * dt) * (1.0f / (dt * dt));
}

// Over-relaxed Jacobi (Macklin et al. 2014, sec. 4.2): the correction
// applied is omega dp (omega = 1: the paper's PBF).
PBF_HD inline Vec3 overRelaxed(const SolverConstants& c, const Vec3& dp) {
    return dp * c.overRelaxation;
}

// ---- Velocity (Alg. 1 l. 21) and its post-processing (eq. 15-17) -------------

// Alg. 1 l. 21: v_i = (x*_i - x_i) / dt.
PBF_HD inline Vec3 velocityFromPositions(const Vec3& x, const Vec3& predicted, float dt) {
    const Vec3 move = predicted - x;
    return {move.x / dt, move.y / dt, move.z / dt};
}

// Eq. 15, the term of neighbour j of the vorticity
// omega_i = sum_j (m / rho_j) grad_i W_ij x (v_j - v_i)
// (the SPH curl with the neighbour's volume m / rho_j).
PBF_HD inline Vec3 vorticityTerm(const SolverConstants& c, const Vec3& rij, const Vec3& vi,
                                 const Vec3& vj, float rhoJ) {
    const float volumeJ = c.particleMass / rhoJ;
    return cross(volumeJ * c.spiky.gradient(rij, length(rij)), vj - vi);
}

// Eq. 16, the term of neighbour j of eta = grad |omega| at x_i, in SPH
// difference form: (m / rho_j) (|omega_j| - |omega_i|) grad_i W_ij.
PBF_HD inline Vec3 vorticityGradientTerm(const SolverConstants& c, const Vec3& rij,
                                         float magnitudeI, float magnitudeJ, float rhoJ) {
    const float volumeJ = c.particleMass / rhoJ;
    return ((magnitudeJ - magnitudeI) * volumeJ) * c.spiky.gradient(rij, length(rij));
}

// Eq. 16: the confinement acceleration a_i = epsilon h |omega_i| (N x omega_i),
// N = eta / |eta|; none where eta vanishes (no direction to push towards).
// epsilon is dimensionless: times h |omega| it is an acceleration.
PBF_HD inline Vec3 vorticityConfinement(const SolverConstants& c, float epsilon, const Vec3& eta,
                                        const Vec3& omega) {
    const float etaLength = length(eta);
    if (!(etaLength > 1e-20f)) return {};
    const Vec3 normal = eta * (1.0f / etaLength);
    return (epsilon * c.h * length(omega)) * cross(normal, omega);
}

// Eq. 17, the term of neighbour j of XSPH viscosity (Schechter & Bridson
// 2012): c_visc 2m / (rho_i + rho_j) (v_j - v_i) W_poly6(r). The symmetric
// volume 2m / (rho_i + rho_j) (the paper uses m / rho_j, sec. 5) makes the
// pair terms equal and opposite, so XSPH conserves momentum.
PBF_HD inline Vec3 xsphTerm(const SolverConstants& c, float viscosity, const Vec3& rij,
                            const Vec3& vi, const Vec3& vj, float rhoI, float rhoJ) {
    const float volume = 2.0f * c.particleMass / (rhoI + rhoJ);
    return (viscosity * volume * c.poly6.value(lengthSquared(rij))) * (vj - vi);
}

}  // namespace pbf::reference
