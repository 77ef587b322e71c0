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
    Aabb domain;                  // walls of the box
    Aabb collisionBox;            // domain shrunk by the particle radius
    WallTable wall;

    static SolverConstants from(const SimulationParams& params);
};

}  // namespace pbf
