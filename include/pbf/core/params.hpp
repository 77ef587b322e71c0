// Simulation parameters: plain structs with documented defaults and ranges.
//
// Everything is in SI units (metres, seconds, kilograms). The paper's
// dimensionless constants (s_corr k, n, dq; the relaxation epsilon; XSPH c)
// are kept dimensionless here and converted to SI inside the solver by the
// rest-lattice scales of the constraint (see SolverConstants): copying the
// paper's numbers verbatim into SI formulas is the "units trap" of
// docs/scenes.md.
#pragma once

#include <string>

#include "pbf/core/vec3.hpp"

namespace pbf {

struct FluidParams {
    float restDensity = 1000.0f;  // rho0, kg/m^3, (0, 1e5]
    // XSPH viscosity c (Schechter & Bridson 2012, paper eq. 17), dimensionless
    // because the sum is weighted by particle volume: [0, 1]. A smoothing of
    // the velocities by a share c per substep, not a material viscosity: its
    // effect depends on the time step and the resolution (docs/validation.md,
    // "Viscosity"). For a viscosity in m^2/s use kinematicViscosity.
    float viscosity = 0.01f;
    // Kinematic viscosity nu, m^2/s, [0, 1]: the SPH Laplacian of the
    // velocity (reference::viscosityTerm), checked against the Taylor-Green
    // vortex's decay exp(-2 nu k^2 t). 0 (the default): none; water is
    // 1.0e-6, far below PBF's own numerical dissipation at usual
    // resolutions. Explicit: the adaptive substep keeps dt <= 0.05
    // (2 r)^2 / nu.
    float kinematicViscosity = 0.0f;
    // Vorticity confinement epsilon (paper eq. 16, Fedkiw et al. 2001),
    // dimensionless: acceleration = epsilon * h * |omega| * (N x omega). [0, 10].
    float vorticity = 0.0f;
    // Surface tension sigma, N/m (water at 20 C: 0.0728), [0, 10]; 0: off.
    // Two forces (docs/surface_tension.md, "The model"): the curvature force
    // sigma kappa on the surface band (Brackbill, Kothe & Zemach 1992; sigma
    // itself, its factors measured on the particles), which gives a drop the
    // Laplace pressure 2 sigma / R and Rayleigh's frequency, and the surface
    // layer's pair cohesion, derived from sigma on the rest lattice
    // (SolverConstants), which holds outlying particles. The walls' and
    // solids' adhesion is derived from it as well.
    float surfaceTension = 0.0f;
};

struct ArtificialPressureParams {
    // s_corr = -k (W(r) / W(dq h))^n, in units of the constraint's lambda
    // scale (paper eq. 13-14: k = 0.1, n = 4, dq = 0.1 .. 0.3 h).
    // Default k = 0.01, not the paper's 0.1: s_corr is a repulsion between
    // every pair, and with the constraint clamped at free surfaces (C >= 0)
    // nothing balances it there, so it acts as an outward acceleration of
    // order k * spacing / dt^2 on spray and thin streams (k = 0.1 turns a
    // poured stream into spray; 0.01 keeps it coherent and still damps the
    // particle pairing seen with k = 0 in a resting tank).
    float k = 0.01f;  // [0, 1]
    int n = 4;        // [1, 8]
    float dq = 0.2f;  // fraction of h, (0, 1)
};

enum class TimeStepMode { Adaptive, Fixed };

// The default of solver.over_relaxation: chosen from the mode
// (SolverParams::effectiveOverRelaxation). With a tolerance
// (maxDensityError > 0) omega = 1.2, which reaches the tolerance in fewer
// iterations (docs/performance.md, "Accuracy per cost"): a user who asks for
// an accuracy gets the faster iteration without knowing the setting. With
// fixed iterations the paper's plain Jacobi (1): the default run is
// unchanged. A value set (1 for plain Jacobi) is used as it is.
inline constexpr float kAutomatic = -1.0f;

struct SolverParams {
    int iterations = 4;  // Jacobi density iterations per substep, [1, 100]
    // Error-controlled iterations (SPlisHSPlasH's maxError): when > 0, each
    // substep iterates until the average compression mean(max(rho/rho0 - 1,
    // 0)), measured by the density pass, is at most this (relative, e.g.
    // 0.0002 = 0.02 %), running at least `minIterations` and at most
    // `maxIterations` corrections; `iterations` is then unused. 0: fixed
    // `iterations`.
    float maxDensityError = 0.0f;  // [0, 0.1]
    int minIterations = 1;         // [0, maxIterations]
    int maxIterations = 100;       // [1, 1000]
    // Over-relaxation of the Jacobi correction: x* += omega dp (Macklin et
    // al. 2014, "Unified particle physics for real-time applications", sec.
    // 4.2: Jacobi with omega > 1 converges faster while it stays stable).
    // Jacobi with omega beyond ~1.5 blew the dam break up (measured: 1.6).
    float overRelaxation = kAutomatic;  // [0.5, 1.5] or kAutomatic (1.2 / 1)
    // Warm start: each substep's iterations start from the prediction plus
    // this fraction of the particle's last pressure acceleration times dt^2,
    // for particles that ended the last substep compressed
    // (reference::warmStart; DFSPH warm-starts its solvers the same way).
    // 0: off (the paper's PBF). 0.8 with over_relaxation 1.2 was the best
    // on the dam break (docs/performance.md, "Accuracy per cost"); 1 feeds
    // energy into violent flows, and so do fewer than ~4 iterations. Not
    // chosen automatically with a tolerance: it makes water at rest boil
    // (a resting tank reaches 0.3 m/s median speed with 0.8 and
    // 4 to 30 iterations, at r = 10, 5 and 2.5 mm; docs/performance.md).
    float warmStart = 0.0f;  // [0, 1]
    // Constraint-force-mixing epsilon of paper eq. 11, relative to the rest
    // lattice's sum |grad C|^2 (so the value means the same at any resolution).
    float relaxation = 0.01f;  // [1e-6, 10]
    // Consistency of the position correction, beta in [0, 1]. Eq. 14 moves
    // particle i by (lambda_i + lambda_j) grad W_ij, which conserves momentum
    // but keeps the term lambda_i sum_j grad W_ij: wherever the water is
    // compressed (under its own weight) that term pulls each particle back
    // to the centre of its neighbours, a stiffness against shear
    // proportional to the pressure (a standing wave runs 14 % fast and
    // loses a sixth of its amplitude per period at r = 5 mm; docs/
    // validation.md, "Standing wave"). beta removes 2 beta lambda_i from the
    // weight: (1 - 2 beta) lambda_i + lambda_j. 0: the paper's form; 0.5:
    // lambda_j alone; 1: lambda_j - lambda_i, exact for a uniform lambda.
    // Above 0 momentum is conserved only where the lambdas are uniform.
    float consistentCorrection = 0.0f;  // [0, 1]
    ArtificialPressureParams artificialPressure;
    // Kernel support h in units of the particle radius (h = 4 r: ~33 neighbours).
    float kernelRadiusFactor = 4.0f;  // [3, 6]

    TimeStepMode timeStepMode = TimeStepMode::Adaptive;
    // Adaptive mode: substep dt = cfl * particle spacing / max speed, within
    // [frame / maxSubsteps, maxTimeStep].
    float cfl = 0.4f;  // (0, 1]
    // The cap matters for slow flows: PBF's residual velocity noise at rest
    // scales with g dt (4 Jacobi iterations remove most, not all, of each
    // step's gravity push), so a resting tank settles at 1/240 s, not 1/60 s.
    float maxTimeStep = 1.0f / 240.0f;  // seconds, (0, 1]
    int maxSubsteps = 200;              // per frame, [1, 10000]
    // Adaptive mode with fixed iterations: substeps short enough that
    // Pi = (depth / spacing) (g dt^2 / spacing) / iterations stays at most
    // this, for the depth the fluid blocks start with (World::depthStep):
    // deeper water erupts at the start (0.2 m at r = 3 mm and 1/240 s:
    // Pi = 0.24). 0: off.
    float depthLimit = 0.1f;  // [0, 1]
    // Fixed mode: exactly this many substeps per frame.
    int fixedSubsteps = 2;  // [1, 10000]

    // Domain-wall response: normal velocity is reflected with `restitution`,
    // tangential velocity is scaled by (1 - friction) on contact.
    float restitution = 0.0f;  // [0, 1]
    float friction = 0.0f;     // [0, 1]
    // Domain walls' adhesion with surface tension on: the work of adhesion in
    // units of the water's work of cohesion 2 sigma, [0, 1]; Young-Dupre's
    // contact angle is acos(2 a - 1): 0 water beads (180 deg), 0.5 neutral
    // (90 deg), 1 wets completely. Solids and bodies have their own.
    float wallAdhesion = 0.0f;

    // The omega the solver runs with: kAutomatic resolved (see there).
    float effectiveOverRelaxation() const {
        return overRelaxation != kAutomatic ? overRelaxation
                                            : (maxDensityError > 0.0f ? 1.2f : 1.0f);
    }
};

struct SimulationParams {
    Aabb domain{{0.0f, 0.0f, 0.0f}, {1.0f, 1.0f, 1.0f}};  // metres; particles never leave it
    Vec3 gravity{0.0f, -9.81f, 0.0f};                     // m/s^2
    float particleRadius = 0.01f;  // metres; spacing of the initial lattice is 2 r
    FluidParams fluid;
    SolverParams solver;

    float particleSpacing() const { return 2.0f * particleRadius; }
    float kernelRadius() const { return solver.kernelRadiusFactor * particleRadius; }
};

// Returns an empty string when valid, else "field: problem" for the first
// invalid field (field names as in scene files, e.g. "solver.iterations").
std::string validate(const SimulationParams& params);

}  // namespace pbf
