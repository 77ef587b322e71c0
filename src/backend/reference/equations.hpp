// The equations of Position Based Fluids (Macklin & Mueller 2013, "Position
// Based Fluids", ACM TOG 32(4)), one short scalar function each, written to
// be read beside the paper (private header).
//
// These are the oracle the fast paths are tested against (STYLE.md: a readable reference beside the fast path):
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

#include <cmath>

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

// Eq. 14, the term of neighbour j: (m/rho0) (lambda_i + lambda_j + s_corr) grad W_ij,
// lambda_i weighted by 1 - 2 solver.consistent_correction (params.hpp).
PBF_HD inline Vec3 positionCorrectionTerm(const SolverConstants& c, float lambdaI, float lambdaJ,
                                          const Vec3& rij) {
    const float weight = c.ownLambdaWeight * lambdaI + lambdaJ + artificialPressure(c, rij);
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

// ---- Surface tension and adhesion -------------------------------------------
//
// Cohesion of the surface layer. A particle is on the surface when its
// density is below SolverConstants::surfaceDensity (0.98 rho0: its kernel
// misses neighbours; the density constraint holds the bulk at rho0). The
// energy of the water is epsilon times the density its surface particles
// miss,
//   E = epsilon sum_i s_i (rho~0 - rho~_i),  rho~_i = m sum_j W(max(r_ij, d)),
// s_i = 1 on the surface, 0 inside, d one particle spacing: a surface
// particle lowers E by gathering neighbours, so the surface contracts, and
// E of a flat surface per unit area is the surface tension. The force,
// -grad E with s frozen for the step, is a pair force
//   a_i = epsilon sum_j (s_i + s_j) grad W(max(r_ij, d)),
// equal and opposite (momentum and angular momentum are conserved) and zero
// between two particles inside the water, so surface tension adds no
// stress to the bulk. It is the pair cohesion of Akinci, Akinci & Teschner
// 2013 (eq. 1-2) and of "pairwise force SPH" (Tartakovsky & Meakin 2005)
// restricted to the surface, with the kernel flat within one spacing as in
// Jeske et al. 2023 (min(W, W(d))): no pair gains by coming closer than the
// rest lattice's spacing, so the cohesion never pulls particles into
// clumps; closer than 0.8 d a core pushes every pair apart (the job of
// Akinci's repulsive core and of PBF's s_corr). docs/surface_tension.md compares the models tried
// (the pair force between all particles made PBF's water a jelly, a continuum surface force from
// particle normals was 3-5 times too strong) and says how epsilon is derived from sigma
// (SolverConstants::cohesionScale = 6 c6 epsilon).

// Whether a particle of this density is on the surface.
PBF_HD inline bool onSurface(const SolverConstants& c, float density) {
    return density < c.surfaceDensity;
}

// ---- Strands: where a neck lets go ------------------------------------------
//
// A neck that thins to about two particles across stops thinning: its
// particles sit within one spacing of each other, where the cohesion's kernel
// is flat (no gain in coming closer), at rest density (the constraint does
// not push), and the curvature force cannot resolve a surface two particles
// across. The strand is force-free and holds its drops together for good;
// the continuum would pinch it within its capillary time sqrt(rho d^3 / sigma)
// (Eggers 1993). So a surface particle whose neighbourhood is narrower than
// the kernel in two directions leaves the surface layer (s = 0): two such
// particles no longer attract, while the drops at the strand's ends still
// pull its last particles in. The measure is the middle eigenvalue of the
// poly6-weighted covariance of the neighbours' offsets about their centroid
// (self included; two small eigenvalues: a strand or a chain, one: a surface
// or a sheet), against SolverConstants::strandSpread2, with the largest
// above SolverConstants::strandLength2 (a strand is long; a clump of a few
// particles is small every way and is not one). A particle within
// reach of a wall or solid is held by it and never counts as a strand (else
// a wetting film's edge would lose its cohesion and spread).

// The neighbour spread's sums: weights, weighted offsets and their products.
struct SpreadSums {
    float weight = 0.0f;
    Vec3 mean;
    float xx = 0.0f, xy = 0.0f, xz = 0.0f, yy = 0.0f, yz = 0.0f, zz = 0.0f;
};
// The term of neighbour j (rij = x_i - x_j), or of the particle itself (rij = 0).
PBF_HD inline void addSpreadTerm(const SolverConstants& c, const Vec3& rij, SpreadSums& s) {
    const float w = c.poly6.value(lengthSquared(rij));
    const Vec3 y = rij * w;
    s.weight += w;
    s.mean += y;
    s.xx += y.x * rij.x;
    s.xy += y.x * rij.y;
    s.xz += y.x * rij.z;
    s.yy += y.y * rij.y;
    s.yz += y.y * rij.z;
    s.zz += y.z * rij.z;
}

// The covariance's middle and largest eigenvalues (m^2), in closed form (the
// trigonometric solution of the characteristic cubic; Smith 1961).
struct SpreadAxes {
    float middle = 0.0f;
    float largest = 0.0f;
};
PBF_HD inline SpreadAxes spreadAxes(const SpreadSums& s) {
    if (!(s.weight > 0.0f)) return {};
    const float inv = 1.0f / s.weight;
    const Vec3 m = s.mean * inv;
    const float a00 = s.xx * inv - m.x * m.x, a01 = s.xy * inv - m.x * m.y,
                a02 = s.xz * inv - m.x * m.z, a11 = s.yy * inv - m.y * m.y,
                a12 = s.yz * inv - m.y * m.z, a22 = s.zz * inv - m.z * m.z;
    const float q = (a00 + a11 + a22) * (1.0f / 3.0f);
    const float b00 = a00 - q, b11 = a11 - q, b22 = a22 - q;
    const float p2 = b00 * b00 + b11 * b11 + b22 * b22 + 2.0f * (a01 * a01 + a02 * a02 + a12 * a12);
    const float p = std::sqrt(p2 * (1.0f / 6.0f));
    if (!(p > 1e-6f * q)) return {q, q};  // isotropic: three equal eigenvalues
    const float det = b00 * (b11 * b22 - a12 * a12) - a01 * (a01 * b22 - a12 * a02) +
                      a02 * (a01 * a12 - b11 * a02);
    float r = det / (2.0f * p * p * p);
    r = r < -1.0f ? -1.0f : (r > 1.0f ? 1.0f : r);
    const float phi = std::acos(r) * (1.0f / 3.0f);
    const float largest = q + 2.0f * p * std::cos(phi);
    const float smallest = q + 2.0f * p * std::cos(phi + 2.0943951f);
    return {3.0f * q - largest - smallest, largest};
}

// Whether a neighbourhood of this spread is a strand below the resolution:
// narrow in two directions and long in the third. A clump of a few
// particles (a satellite drop, a pair) is small in all three: it keeps its
// cohesion, holds together and can rejoin the water it meets.
PBF_HD inline bool inStrand(const SolverConstants& c, const SpreadSums& spread) {
    const SpreadAxes axes = spreadAxes(spread);
    return axes.middle < c.strandSpread2 && axes.largest > c.strandLength2;
}

// The pair weight: (s_i + s_j) (h^2 - r^2)^2 for d < r < h (the pull, the
// gradient of W_poly6 without -6 c6 r), 0 between r_c and d (the kernel's
// flat top), and -2 coreScale (r_c - r)^2 / r below the core distance r_c
// for every pair, inside the water too: a push apart, so that no two
// particles sit on one another. It takes over the job of s_corr (off with
// surface tension: without either, PBF pairs particles up) as a force,
// whose strength does not depend on the time step.
PBF_HD inline float cohesionWeight(const SolverConstants& c, float r2, bool surfaceI,
                                   bool surfaceJ) {
    if (r2 < c.cohesionCoreDistance2) {
        // (r_c - r)^2 / r: times (x_i - x_j) a push of (r_c - r)^2, not
        // vanishing as r -> 0 (the spiky kernel's reason, Mueller et al. 2003).
        const float r = std::sqrt(r2);
        const float core = c.cohesionCoreDistance - r;
        return r > 0.0f ? -2.0f * c.cohesionCoreScale * core * core / r : 0.0f;
    }
    if (!(r2 > c.cohesionMinDistance2) || !(r2 < c.poly6.h2)) return 0.0f;
    const float q = c.poly6.h2 - r2;
    return (float(surfaceI) + float(surfaceJ)) * (q * q);
}

// The term of neighbour j of the cohesion acceleration,
// epsilon (s_i + s_j) grad W (and the core) = -cohesionScale weight (x_i - x_j).
PBF_HD inline Vec3 cohesionTerm(const SolverConstants& c, const Vec3& rij, bool surfaceI,
                                bool surfaceJ) {
    return rij * (-c.cohesionScale * cohesionWeight(c, lengthSquared(rij), surfaceI, surfaceJ));
}

// Adhesion (Akinci, Akinci & Teschner 2013, eq. 6, with the distance-field
// boundary of backend/boundary.hpp): a wall or solid pulls a particle as the
// rest lattice continued beyond its surface would through the pair
// potential U(r) = -k m^2 W_poly6(max(r, d)), weighted by its adhesion a;
// `pull` is the weighted WallTable::cohesionSum (m^5, into the boundary). k
// is derived from sigma so that separating two half-lattices takes 2 sigma
// per area: the boundary's work of adhesion is a 2 sigma, and Young-Dupre
// gives the contact angle cos(theta) = 2 a - 1.
PBF_HD inline Vec3 adhesionAcceleration(const SolverConstants& c, const Vec3& pull) {
    return c.adhesionScale * pull;
}

// ---- Curvature force (the static surface tension) --------------------------
//
// The cohesion above holds outlying particles but no static tension: its
// in-plane pull compresses the layer until the density constraint pushes
// back. The tension's pressure jump
// sigma kappa is applied as the continuum surface force (Brackbill, Kothe &
// Zemach 1992, J. Comput. Phys. 100, eq. 21; Morris 2000, Int. J. Numer.
// Meth. Fluids 33, for SPH) on the particles of the surface band:
//   g_i = sum_j V grad W_ij            (V = m / rho0, spiky: grad c, 1/m)
//   A_i = max(|g_i| - g0 / d, 0),      n_i = -g_i / |g_i| (outward)
//   a_i = -sigma kappa_i delta_i n_i / rho0
// with both factors measured, not calibrated (docs/surface_tension.md,
// "The model"):
//  - kappa from the surface's own geometry: on a sphere of radius R,
//    (n_i - n_j) . x_ij = |x_ij|^2 / R, so over the band's neighbours, in
//    least squares, kappa_i = 2 sum W (nb_i - nb_j) . x_ij / sum W |x_ij,t|^2
//    (poly6 W; x_ij,t the part of x_ij across nb_i: a neighbour at another
//    depth adds nothing to the numerator). nb are the normals averaged over
//    the band's neighbours, the particle's own left out: a particle's own
//    n follows its offset from its neighbours, and with it kappa read the
//    particle-scale roughness of a surface without viscosity (3 times 2 / R
//    on the Rayleigh drop). kappa is then averaged over the band (weights
//    W A).
//  - delta_i = A_i / D_i, D_i = sum_j V A_j w2(|x_ij,t|) (self included, w2
//    the 2D poly6 4 (h^2 - r^2)^3 / (pi h^8) of the distance across n_i):
//    the band's column integral of A through x_i, so that delta integrates
//    to one across the surface at any resolution and curvature.
//  - the band lies a depth e inside the interface (the particles' volume
//    ends half a spacing beyond the outer layer): the jump acts on the
//    interface's area, (R / r)^2 times the band's, so the force's kappa is
//    2 R / r^2 = kappa (1 + kappa e / 2) (kept in [0.5, 1.5]: a lone
//    particle's kappa ~ 1 / d says nothing of an interface).
// The walls and solids are not counted in g: a layer on a wall reads as
// flat there (kappa ~ 0, no force) and the adhesion wets it.
// SolverConstants: surfaceTension sigma (N/m), surfaceFloor g0 / d (1/m),
// surfaceOffset e (m).

// The term of neighbour j of g_i = grad c at x_i: V grad W_ij.
PBF_HD inline Vec3 colourGradientTerm(const SolverConstants& c, const Vec3& rij) {
    return c.spiky.gradient(rij, length(rij)) * (c.particleMass / c.restDensity);
}

// A_i: how far |g_i| is above the band's floor (0 off the band, and for a
// g that is not finite).
PBF_HD inline float surfaceBandWeight(const SolverConstants& c, const Vec3& g) {
    const float n = std::sqrt(lengthSquared(g));
    return n > c.surfaceFloor ? n - c.surfaceFloor : 0.0f;
}

// n_i = -g_i / |g_i|, outward (g points into the liquid); only on the band.
PBF_HD inline Vec3 outwardNormal(const Vec3& g) {
    return g * (-1.0f / std::sqrt(lengthSquared(g)));
}

// The term of band neighbour j of the averaged normal: W_ij A_j n_j.
PBF_HD inline Vec3 bandNormalTerm(const SolverConstants& c, const Vec3& rij, const Vec3& gj) {
    return outwardNormal(gj) * (c.poly6.value(lengthSquared(rij)) * surfaceBandWeight(c, gj));
}

// The least-squares curvature's sums over the band's neighbours: the
// numerator sum W (nb_i - nb_j) . x_ij, and sum W |x_ij,t|^2 and
// sum W |x_ij|^2.
struct CurvatureSums {
    float slope = 0.0f;
    float across = 0.0f;
    float total = 0.0f;
};
PBF_HD inline void addCurvatureTerm(const SolverConstants& c, const Vec3& rij, const Vec3& nbI,
                                    const Vec3& nbJ, CurvatureSums& sums) {
    const float r2 = lengthSquared(rij);
    const float w = c.poly6.value(r2);
    const float along = dot(nbI, rij);
    sums.slope += w * dot(nbI - nbJ, rij);
    sums.across += w * (r2 - along * along);
    sums.total += w * r2;
}
// kappa_i (1/m) from the sums: a particle whose neighbours lie along its
// normal (a tip, spray) has no spread across it to fit over; half the full
// sum stands in for it there.
PBF_HD inline float curvatureOf(const CurvatureSums& sums) {
    const float across = sums.across > 0.5f * sums.total ? sums.across : 0.5f * sums.total;
    return across > 0.0f ? 2.0f * sums.slope / across : 0.0f;
}

// The 2D poly6 of the distance across n_i (the column integral's weight),
// 1/m^2; 0 beyond h.
PBF_HD inline float columnWeight(const SolverConstants& c, const Vec3& rij, const Vec3& ni) {
    const float along = dot(rij, ni);
    const float d = c.h * c.h - (lengthSquared(rij) - along * along);
    if (!(d > 0.0f)) return 0.0f;
    const float h2 = c.h * c.h;
    return 4.0f / (3.14159265f * h2 * h2 * h2 * h2) * d * d * d;
}

// a_i from the band-averaged kappa, A_i and the column sum D_i (m^-1):
// -sigma kappa_f (A_i / D_i) n_i / rho0 (dt = 1: the acceleration).
PBF_HD inline Vec3 curvatureForceVelocityChange(const SolverConstants& c, float dt, const Vec3& gi,
                                                float kappa, float columnSum) {
    const float weight = surfaceBandWeight(c, gi);
    if (!(weight > 0.0f) || !(columnSum > 0.0f)) return {};
    float scale = 1.0f + 0.5f * kappa * c.surfaceOffset;
    scale = scale < 0.5f ? 0.5f : (scale > 1.5f ? 1.5f : scale);
    return outwardNormal(gi) *
           (-dt * c.surfaceTension * kappa * scale * (weight / columnSum) / c.restDensity);
}

// ---- Physical viscosity (an addition to the paper) ---------------------------
//
// XSPH (eq. 17) smooths velocities by a fraction c per step: its viscosity
// depends on dt and the resolution and is not a material constant
// (docs/validation.md, Taylor-Green). `fluid.kinematic_viscosity` nu (m^2/s) adds the SPH
// Laplacian of the velocity that SPH codes use for a physical viscosity
// (Monaghan 2005, "Smoothed particle hydrodynamics", Rep. Prog. Phys. 68,
// sec. 6.1; SPlisHSPlasH's standard viscosity), a_i = nu lap v_i with
//   lap v_i = 2 (d + 2) sum_j V_ij (v_ij . x_ij) / (|x_ij|^2 + 0.01 h^2) grad_i W_ij,
// d = 3, v_ij = v_i - v_j, x_ij = x_i - x_j, and the symmetric volume
// V_ij = 2 m / (rho_i + rho_j) (as XSPH's) so that the pair terms are equal
// and opposite and momentum is conserved. 0.01 h^2 keeps close pairs finite.

// The term of neighbour j of a_i (m/s^2), before the normalisation below.
PBF_HD inline Vec3 viscosityTerm(const SolverConstants& c, float nu, const Vec3& rij,
                                 const Vec3& vi, const Vec3& vj, float rhoI, float rhoJ) {
    const float r2 = lengthSquared(rij);
    const float volume = 2.0f * c.particleMass / (rhoI + rhoJ);
    const float scale = 10.0f * nu * volume * dot(vi - vj, rij) / (r2 + 0.01f * c.h * c.h);
    return scale * c.spiky.gradient(rij, length(rij));
}

// The sum above is the Laplacian only where the neighbours fill the kernel
// like a continuum. With h = 4 r it holds ~33 neighbours: on the rest
// lattice it gives 0.65 of lap v, more where the particles are disordered
// (measured on the Taylor-Green vortex: the decay rate followed neither).
// So it is normalised by the same sum of the particle's own neighbours for
// the fields it must get right: v_a = x_b^2 (a != b), whose Laplacian is 2
// and whose sum is M_ab = -10 sum_j V_ij x_a^2 x_b^2 F(r) (x = x_ij,
// F = W'(r) / (r (r^2 + 0.01 h^2))); a_i = (2 / M) sum_j term_j with M the
// mean of the six M_ab. This is the term of neighbour j of 6 M (m^2 / m^2:
// dimensionless, 2 on a continuum).
PBF_HD inline float viscosityMomentTerm(const SolverConstants& c, const Vec3& rij, float rhoI,
                                        float rhoJ) {
    const float r2 = lengthSquared(rij);
    const float r = length(rij);
    if (!(r > 0.0f) || !(r < c.h)) return 0.0f;
    const float volume = 2.0f * c.particleMass / (rhoI + rhoJ);
    const float d = c.h - r;
    const float slopeOverR = c.spiky.gradientCoefficient * d * d / r;  // W'(r) / r
    const float x2 = rij.x * rij.x, y2 = rij.y * rij.y, z2 = rij.z * rij.z;
    return -10.0f * volume * slopeOverR / (r2 + 0.01f * c.h * c.h) * 2.0f *
           (x2 * y2 + y2 * z2 + z2 * x2);
}
// a_i from the summed terms and the summed moment terms (6 M). The factor
// 2 / M is kept at most 2 (M >= 1): a particle with few neighbours (a
// corner, a splash) has a small M, and an explicit step with a large factor
// would be unstable (a 0.1 m vortex at r = 2.5 mm blew up without it).
PBF_HD inline Vec3 normalisedViscosity(const Vec3& termSum, float momentSum) {
    return termSum * (12.0f / (momentSum > 6.0f ? momentSum : 6.0f));
}

// The domain's walls are free-slip (friction 0 by default): for the
// Laplacian each wall within h of x_i mirrors particle i and its
// neighbours, positions reflected in the wall's plane and the normal
// velocity reversed (the standard mirror condition of a free-slip wall;
// without it the Laplacian near a wall misses the neighbours beyond it and
// a shear flow along a wall decays too slowly). `axis` 0-2, `side` -1 for
// the wall at domain.min, +1 for domain.max.
PBF_HD inline float wallPlane(const SolverConstants& c, int axis, int side) {
    return side < 0 ? c.domain.min[axis] : c.domain.max[axis];
}
PBF_HD inline Vec3 mirrored(const Vec3& x, int axis, float plane) {
    Vec3 m = x;
    float* component = axis == 0 ? &m.x : (axis == 1 ? &m.y : &m.z);
    *component = 2.0f * plane - *component;
    return m;
}
PBF_HD inline Vec3 mirroredVelocity(const Vec3& v, int axis) {
    Vec3 m = v;
    float* component = axis == 0 ? &m.x : (axis == 1 ? &m.y : &m.z);
    *component = -*component;
    return m;
}
// Whether the wall (axis, side) is close enough to x for mirror images to be neighbours.
PBF_HD inline bool wallInReach(const SolverConstants& c, const Vec3& x, int axis, int side) {
    const float distance = side < 0 ? x[axis] - c.domain.min[axis] : c.domain.max[axis] - x[axis];
    // An image of a particle (at least r from the wall) is within h of x
    // only if x is within h - r of the wall.
    return distance < c.wall.range;
}

}  // namespace pbf::reference
