// Shared by the stage tests of the CPU backend's SIMD passes
// (stages_vs_reference_test.cpp) and of the GPU backend's kernels
// (tests/backend/gpu/device_stages_test.cpp): random particle clouds, the
// reference's results on them, the exact values with their float error
// bounds, and the comparison of an implementation's stage outputs with both.
//
// ---- Tolerances (derivation) -------------------------------------------------
//
// Both implementations compute the same formulas from the same float inputs
// (x*, x, the shared constants of SolverConstants, the walls' and solids'
// terms from backend/boundary.hpp), in different orders: the SIMD code sums by
// lanes and tree sums, applies the kernels' coefficients after the sum, and
// gets 1/r from a hardware estimate refined by one Newton step; the
// reference sums in list order with the coefficients in every term and
// divides by r = sqrt(r^2). Neither is exact. For every particle and
// quantity the test evaluates the exact value V (in double, on the same
// float inputs) together with a bound E on |computed - V| that holds for
// both implementations (error_bound.hpp: running error analysis in the
// standard model fl(a op b) = (a op b)(1 + delta), |delta| <= u = 2^-24).
// It checks |simd - V| <= E, |ref - V| <= E and so |simd - ref| <= 2 E.
// The GPU backend's kernels call the reference's own functions
// (neighbor_sums.hpp) with the neighbours in another order: its results
// are within the same bounds (the reference's roundings are inside them).
//
// The bound is built from:
//   * Sums: a float sum of n terms in any order is within
//     gamma_{n-1} sum_k |a_k| of the exact sum of its terms,
//     gamma_n = n u / (1 - n u); sum_k |a_k| is computed per particle. Two
//     orders therefore differ by at most 2 gamma_{n-1} sum |a_k|.
//   * Products: a product of exact factors computed with k roundings in
//     any order, constant factors applied per term or after the sum
//     included, has relative error gamma_k. k is counted for each term as
//     the larger of the two implementations' counts:
//       rho term  m c6 (h^2 - r^2)^3             k = 4 (ref: c6 d d d, m; simd: d^3, c6, m)
//       grad C    m/rho0 cS (h - r)^2 / r dx     k = 5
//       |grad C|^2 (m/rho0 cS)^2 (h - r)^4       k = 13 (ref: square of the vector, sum of 3)
//       s_corr ratio c6 (h^2 - r^2)^3 / W(dq)    k = 4, its n-th power n - 1 more, times k: 1
//       dp term   (lambda_i + lambda_j + s_corr) m/rho0 cS (h - r)^2 / r dx   k = 6
//       XSPH term c 2m c6 (h^2 - r^2)^3 / (rho_i + rho_j) (v_j - v_i)       k = 7
//       omega     m/rho_j cS (h - r)^2 / r dx (one factor of the cross product) k = 7
//       cohesion  S (s_i + s_j) (h^2 - r^2)^2 dx, S = cohesionScale         k = 4
//                 (ref: S pairs, q, q, times dx; simd: q q, pairs, S after the sum)
//       its core  S 2 L (r_c - r)^2 / r dx (every pair)                    k = 6
//   * Cancellation in the kernels' arguments: r^2 = dx^2 + dy^2 + dz^2 has
//     relative error gamma_3 (positive terms, any order, with or without FMA),
//     so h^2 - r^2 has the absolute error gamma_3 r^2 + u |h^2 - r^2|, which
//     is propagated through (h^2 - r^2)^3 exactly (not as a relative error:
//     near r = h it is large relative to the term, small in absolute terms).
//   * 1/r: SIMD: rsqrt estimate e0 (AVX-512 rsqrt14: |e0| <= 2^-14; AVX2:
//     1.5 2^-12) and one Newton step y (1.5 - 0.5 x y^2): exact-arithmetic
//     error 1.5 e0^2 + 0.5 |e0|^3 <= 3.4 u, plus three roundings in the step
//     (y^2 and 0.5 x y^2 near 0.5, 1.5 - that near 1, times y): eps_rs <= 7 u.
//     (x86 targets: SSE4 / AVX2 rsqrtps, AVX-512 rsqrt14. Highway's estimate
//     on other instruction sets is coarser; there eps_rs must be re-derived.)
//     With r^2's gamma_3 (halved by the square root) 1/r has relative error
//     eps_inv = (1 + eps_rs)(1 + gamma_3) - 1, and r = r^2 / sqrt(r^2) the
//     same plus one rounding; the reference's sqrt and division are inside
//     these. h - r is propagated like h^2 - r^2.
//   * Surface tension's cohesion acts between d < r < h (d one spacing): a
//     pair with r^2 within rounding of d^2 is ambiguous like one at h, but
//     its term is not small; it is added whole to E (such pairs are rare in
//     random clouds). Both implementations get the same densities (so the
//     same surface flags s) and the same adhesion (backend/boundary.hpp on the
//     same x), added in the same order; v + dt a rounds twice.
//   * Pairs at r ~ h: the lists and the kernels' support tests compare the
//     rounded r^2 with h^2, so a pair with |r^2 - h^2| within the rounding
//     may be counted by one implementation and not the other. Such pairs add
//     their whole term (value + bound; it is tiny: (h^2 - r^2)^3 or
//     (h - r)^2 with h - r ~ u h) to E.
//   * The walls' and solids' terms are shared floats (the same functions on
//     the same x); only their kernel sum is added in another order (up to 6
//     walls + 1 solid: counted as 6 extra terms of the density sum).
//   * Propagation: C = max(rho/rho0 - 1, 0) takes rho's absolute error
//     (divided by rho0) plus the roundings of the product and of the
//     subtraction; near rest density C is small and its relative error
//     large, which is why lambda = -C / (sum |grad C|^2 + eps) gets an
//     absolute bound. dp uses lambda_i, lambda_j with their bounds;
//     XSPH and omega use rho_j and v = (x* - x) / dt (relative gamma_2: the
//     SIMD multiplies by the rounded 1/dt) with theirs. The corrected x*
//     is compared as clamp(x* + dp) - x*: the addition adds u |x* + dp| and
//     the box clamp is 1-Lipschitz, so the clamped results stay comparable.
// The test asserts the bounds; it prints how much of 2 E the largest
// SIMD-vs-reference difference uses and how large E is relative to the
// quantity, to show that the bound is tight enough to catch a wrong term.
#pragma once

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "pbf/core/params.hpp"
#include "pbf/core/solver_constants.hpp"
#include "pbf/core/vec3.hpp"
#include "pbf/geometry/solids.hpp"

namespace pbf::test {

// The step length the clouds' velocities are measured with.
inline constexpr float kStageDt = 1.0f / 240.0f;

struct Cloud {
    std::string name;
    SimulationParams params;
    std::unique_ptr<SolidSet> solids;  // null: none
    std::vector<Vec3> predicted;       // x*
    std::vector<Vec3> velocity;        // v; the start of the step is x = x* - dt v
};

// n particles at rest density on average: one per spacing^3.
Cloud uniformCloud(std::size_t n);
// Dense Gaussian blobs: several times rest density in their cores.
Cloud clusteredCloud(std::size_t n);
// A cloud in a corner of the domain, touching three walls; a tenth of the
// particles lie exactly on the collision box's faces (as clamped ones do).
Cloud wallCloud(std::size_t n);
// Particles around a sphere and a box, at least one radius outside them.
Cloud solidCloud(std::size_t n);

// Surface tension on the clouds: water's sigma, adhesion on the walls and on
// the solid cloud's sphere, so that the walls' and solids' pulls are compared too.
inline constexpr float kStageWallAdhesion = 0.7f;
// The cloud's settings with water's sigma and solver.wall_adhesion =
// kStageWallAdhesion, and their constants.
SimulationParams surfaceTensionParams(const Cloud& cloud);
SolverConstants surfaceTensionConstants(const Cloud& cloud);

// One implementation's outputs of the stages of a step, in its particle
// order: density and lambda at x*, the corrected x* = clamp(x* + dp) (out of
// the solids), v = (x* - x) / dt, v after XSPH, the vorticity, and v + dt a
// with surface tension's acceleration at x* from the implementation's
// densities (empty: the implementation has no surface tension; not compared).
struct StageResults {
    std::vector<Vec3> x, xStar;  // the inputs, in the implementation's order
    std::vector<float> density, lambda;
    std::vector<Vec3> corrected, velocity, xsphVelocity, vorticity;
    std::vector<float> surfaceLayer;  // s, the surface layer's weights (with surface tension)
    std::vector<Vec3> surfaceTensionVelocity;
};

// Compares `results` (of `implementation`, e.g. "simd") with the reference
// and the exact values within the derived bounds (gtest expectations), and
// checks that the cloud exercised what it is meant to.
void expectAgreementWithReference(const Cloud& cloud, const SolverConstants& c,
                                  const StageResults& results, const char* implementation,
                                  const std::string& label);

// The physical viscosity (fluid.kinematic_viscosity): an implementation's
// stage applied to the velocities v with the step `stepDt` gave `after`
// (= v + stepDt a); x*, v and rho are its inputs in its particle order. The
// stage and reference::viscosityAcceleration call the same terms
// (equations.hpp: viscosityTerm, viscosityMomentTerm, the wall mirrors) on
// the same floats and differ only in the order of the neighbours; both
// sums (terms and moment) therefore agree within 2 gamma_{n-1} sum |terms|
// each, propagated through the normalisation 12 / moment. Returns the
// largest |stage - reference| over the sum of the terms' magnitudes
// (normalised as the sum is), the read-back's roundings allowed; the tests
// ask for less than kViscosityAgreement (far above that rounding, far below
// a missing mirror or a dropped term: each is at least a few percent of the
// sum at a wall). Prints it with the number of wall contacts.
inline constexpr double kViscosityAgreement = 1e-4;
double physicalViscosityDeviation(const Cloud& cloud, const SolverConstants& c, float nu,
                                  const std::vector<Vec3>& xStar, const std::vector<Vec3>& v,
                                  const std::vector<float>& density, const std::vector<Vec3>& after,
                                  float stepDt);

// The curvature force (equations.hpp, "Curvature force"): an
// implementation's passes (g, nb, kappa for every particle in turn, then the
// force) at x* (its particle order) gave the accelerations `a`. They call
// the reference's per-particle sums (neighbor_sums.hpp) on the same floats,
// in another neighbour order; the passes normalise, divide and subtract
// nearby normals (kappa's numerator cancels to ~ |x_ij| / R of its terms),
// so a rounding bound as the other stages' is not derived: the agreement
// asked is kCurvatureAgreement of the band's rms |a| plus |a_ref| per
// particle, which a dropped pass, a field read from the wrong pass, a
// wrong sign or scale (all O(1) of |a|) exceed by orders of magnitude. A
// particle whose |g| lies within 1e-4 of the band's floor may be on the
// band in one order and off it in another: the particles within 3 h of one
// are left out (and must be few). Returns the largest deviation over the
// bound (the tests ask for <= 1) and prints it with the band's share.
inline constexpr double kCurvatureAgreement = 1e-3;
double curvatureForceDeviation(const Cloud& cloud, const SolverConstants& c,
                               const std::vector<Vec3>& xStar, const std::vector<Vec3>& a);

}  // namespace pbf::test
