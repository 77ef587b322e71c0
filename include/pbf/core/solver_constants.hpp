// SI constants of the PBF equations, derived once from SimulationParams and
// shared by every backend (the SIMD CPU solver, the scalar reference).
//
// Units trap (docs/scenes.md, "Units"): the paper's relaxation epsilon and
// s_corr k are dimensionless; they are scaled here by the rest lattice's
// sum_k |grad_k C_i|^2 so that the same numbers mean the same at every
// particle size.
#pragma once

#include "pbf/core/kernels.hpp"
#include "pbf/core/params.hpp"
#include "pbf/core/vec3.hpp"

namespace pbf {

// Density contribution of a flat wall of the domain box, tabulated against
// the distance s from the wall. The wall is modelled as the rest lattice
// continued beyond the plane (layers at s + r + k 2r), so a particle of the
// initial lattice next to a wall has exactly rest density and fluid at a wall
// is neither under-dense nor pulled towards it (the same role as the boundary
// particles of Akinci et al. 2012, here for the box in closed form).
struct WallTable {
    static constexpr int kSamples = 64;
    float range = 0.0f;                    // distances beyond this see no wall (h - r)
    float inverseStep = 0.0f;              // samples per metre
    float kernelSum[kSamples + 1] = {};    // sum over wall lattice of W, 1/m^3
    float gradientSum[kSamples + 1] = {};  // |sum of spiky grad W|, 1/m^4, points into the wall
    // sum over the wall lattice (beyond one spacing) of (h^2 - r^2)^2 times
    // the distance across the wall, m^5: the pull the wall would give a
    // particle if it were water, in units of SolverConstants::cohesionScale
    // (adhesion, backend/reference/equations.hpp).
    float cohesionSum[kSamples + 1] = {};
};

struct SolverConstants {
    float h = 0.0f;             // kernel radius, m
    float particleMass = 0.0f;  // kg, so that a full rest lattice has density rho0
    float restDensity = 0.0f;   // kg/m^3
    float inverseRestDensity = 0.0f;
    float particleRadius = 0.0f;  // m
    Poly6Kernel poly6;
    SpikyKernel spiky;
    // sum_k |grad_k C_i|^2 of an interior particle of the rest lattice, 1/m^2.
    // It converts the dimensionless relaxation and s_corr k to SI (units trap).
    float restGradientSum = 0.0f;
    float relaxationEpsilon = 0.0f;  // relaxation * restGradientSum
    // s_corr(r) = scorrScale * (W(r) / W(dq h))^n, scorrScale = -k / restGradientSum.
    float scorrScale = 0.0f;
    float scorrInverseWdq = 0.0f;  // 1 / W(dq h)
    int scorrExponent = 4;
    float overRelaxation = 1.0f;  // omega: x* += omega dp (SolverParams::overRelaxation)
    // Weight of lambda_i in eq. 14's pair term: 1 - 2 solver.consistent_correction.
    float ownLambdaWeight = 1.0f;
    // Surface tension (backend/reference/equations.hpp, "Surface tension";
    // docs/surface_tension.md); all 0 while it is off. Pairs of which at
    // least one particle is on the surface (density below surfaceDensity)
    // and that are farther apart than one spacing d attract:
    //   a_i = -cohesionScale sum_j (s_i + s_j) (h^2 - r_ij^2)^2 (x_i - x_j),
    // s = 1 on the surface, 0 inside; cohesionScale = 6 c6 epsilon, epsilon
    // the energy per unit of missing density, from sigma (solver_constants.cpp).
    // Closer than the core distance r_c (0.8 d) every pair repels, with the
    // weight -2 coreScale (r_c - r)^2 / r (coreScale: a push at r = 0 ten
    // times the largest pull, 2 (h^2 - d^2)^2 d): what keeps particles apart
    // (s_corr's job, off with surface tension).
    float cohesionScale = 0.0f;
    float cohesionMinDistance2 = 0.0f;   // d^2, m^2
    float cohesionCoreDistance2 = 0.0f;  // r_c^2, m^2
    float cohesionCoreDistance = 0.0f;   // r_c, m
    float cohesionCoreScale = 0.0f;      // 1
    float surfaceDensity = 0.0f;         // kg/m^3: 0.98 rho0
    // A surface particle whose neighbourhood is narrower than the kernel in
    // two directions (a strand about two particles across, or a chain: the
    // middle eigenvalue of its neighbours' spread below strandSpread2, the
    // largest above strandLength2) is below the resolution and leaves the
    // surface layer, so that a neck thinner than the particles lets go
    // (equations.hpp, "Strands").
    float strandSpread2 = 0.0f;  // m^2: 0.16 d^2
    float strandLength2 = 0.0f;  // m^2: 0.26 d^2
    // Adhesion: a boundary pulls as the rest lattice beyond it would through
    // the pair potential U(r) = -k m^2 W_poly6(max(r, d)) whose work of
    // cohesion on the lattice is 2 sigma: a = adhesion adhesionScale
    // WallTable::cohesionSum, adhesionScale = 6 c6 k m.
    float adhesionScale = 0.0f;
    // The curvature force (Brackbill et al. 1992; equations.hpp, "Curvature
    // force"): a_i = -surfaceTension kappa_i delta_i n_i / rho0 on the band
    // |g_i| > surfaceFloor, g_i = sum_j (m / rho0) grad W_ij, the band lying
    // surfaceOffset inside the interface; the static surface tension, beside
    // the cohesion above. All 0 while surface tension is off.
    float surfaceTension = 0.0f;  // sigma, N/m
    float surfaceFloor = 0.0f;    // g0 / d, 1/m
    float surfaceOffset = 0.0f;   // e, m
    // Largest substep with surface tension: 1 / omega_max, omega_max^2 a
    // bound on the cohesion's stiffness per unit mass on the rest lattice
    // (both particles of every pair on the surface: 2 epsilon sum over the
    // neighbours of |W''| + 2 |W'| / r, Gershgorin over the pair Hessians),
    // half the stability limit 2 / omega of the explicit force; infinite
    // while surface tension is off.
    float capillaryTimeStep = 0.0f;
    Aabb domain;        // walls of the box
    Aabb collisionBox;  // domain shrunk by the particle radius
    WallTable wall;

    static SolverConstants from(const SimulationParams& params);
};

}  // namespace pbf
