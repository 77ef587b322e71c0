#include "pbf/core/solver_constants.hpp"

#include <cmath>
#include <limits>

namespace pbf {
namespace {

// Sums the kernels over the wall's lattice for distances s in [0, h - r].
WallTable makeWallTable(const SolverConstants& c, double radius, double spacing) {
    WallTable table;
    table.range = static_cast<float>(c.h - radius);
    table.inverseStep = WallTable::kSamples / table.range;
    const int reach = static_cast<int>(std::ceil(c.h / spacing));
    for (int sample = 0; sample <= WallTable::kSamples; ++sample) {
        const double s = double(sample) / table.inverseStep;
        double kernelSum = 0.0, gradientSum = 0.0, cohesionSum = 0.0;
        for (int layer = 0; s + radius + layer * spacing < c.h; ++layer) {
            const double depth = s + radius + layer * spacing;  // normal distance to the layer
            for (int a = -reach; a <= reach; ++a)
                for (int b = -reach; b <= reach; ++b) {
                    const Vec3 rij{float(a * spacing), float(b * spacing), float(depth)};
                    kernelSum += c.poly6.value(lengthSquared(rij));
                    gradientSum -= c.spiky.gradient(rij, length(rij)).z;  // component into the wall
                    // Surface tension's pull: pairs beyond one spacing (equations.hpp).
                    const double r2 = lengthSquared(rij);
                    if (r2 > spacing * spacing && r2 < double(c.h) * c.h) {
                        const double q = double(c.h) * c.h - r2;
                        cohesionSum += q * q * depth;
                    }
                }
        }
        table.kernelSum[sample] = static_cast<float>(kernelSum);
        table.gradientSum[sample] = static_cast<float>(gradientSum);
        table.cohesionSum[sample] = static_cast<float>(cohesionSum);
    }
    return table;
}

// A particle is on the surface when its density is 2 % below rest density:
// the bulk's (held at rho0 by the density constraint, compressed rather
// than stretched) never is, the outermost layer of the rest lattice misses
// 19 %.
constexpr double kSurfaceDeficit = 0.02;

// Particles closer than this many spacings repel (equations.hpp): without
// it, and without s_corr, PBF pairs particles up (a cube of water turning
// into a sphere had 200 of 4096 particles within half a spacing of another).
constexpr double kCoreDistance = 0.8;
// The core's push at r = 0 in units of the largest pull of a pair.
constexpr double kCoreStrength = 40.0;

// The lattice derivation of epsilon assumes the outermost layer of the rest
// lattice; a free surface of moving particles packs its outer layer
// tighter (the cohesion pulls it in until the density constraint holds it),
// missing less density, and its surface energy per area is smaller. The
// factor is calibrated once with the Rayleigh frequency of a free drop
// (pbf validate rayleigh_drop; docs/surface_tension.md), not per scene.
constexpr double kCohesionCalibration = 2.5;

// The static surface tension is the curvature force's (Brackbill et al.
// 1992; equations.hpp, "Curvature force"): the cohesion's pull alone
// compresses the layer in-plane until the density constraint pushes back,
// so it holds no static tension (docs/surface_tension.md, "Why this
// model"). The force applies sigma itself, its two factors measured rather
// than fitted: no calibration factor. The cohesion stays at a fraction of its pull
// (kCohesionPull), to hold outlying particles, its core kept. Two lengths
// of the discretisation: the band's floor g0 = 0.2 / d on |grad c| (the
// bulk's noise gives every particle some |g|; on the rest lattice, h = 2 d,
// only the outer layer has |g| d > 0: 0.478) and the band's depth inside
// the interface, e = 0.7 d (on resting drops of 6 and 12 spacings
// in radius the force's total on the upper half fell short of its radial
// integral as a shell 0.74 and 0.70 d inside the volume's radius would;
// the band's A-weighted mean radius lies 0.75 and 0.78 d inside it, as
// the laplace case prints; 0.37 d on a ball cut from the lattice, before
// the surface packs). A pull of 0.45, enough to hold outlying particles
// beside the force: the full laplace, rayleigh_drop, cube_to_sphere and
// wetting cases pass with it (docs/surface_tension.md, "Validation").
constexpr float kSurfaceFloor = 0.2f;    // g0: the floor on |g| times the spacing d
constexpr float kSurfaceOffset = 0.7f;   // e / d
constexpr double kCohesionPull = 0.45;        // the cohesion's pull, of the lattice derivation's

// A strand is below the resolution when the middle eigenvalue of its
// particles' neighbour spread (equations.hpp, "Strands") is under this many
// d^2. Measured on particles: a neck that stopped thinning at about two
// particles across reads 0.12 d^2 (90 % below 0.14), a chain 0; the rest
// lattice's edges 0.20 and corners 0.21, a flat surface 0.40, a drop's
// surface layer 0.31 or more. A uniform disc of radius a reads a^2 / 4: the
// threshold is a strand 1.6 spacings across.
constexpr double kStrandSpread = 0.16;
// ... and a strand is long: the largest eigenvalue over this many d^2. A
// chain's inner particles read 0.46, a thinning neck's 0.30-0.43 (10 % and
// 90 %); a pair 0.9 d apart 0.21, the pieces of 2-9 particles that a
// breaking stream sheds 0.20 (90 % below 0.24). Those are drops below the
// resolution, not strands: they keep their cohesion and stay together.
constexpr double kStrandLength = 0.26;

// The cohesion potential's two lattice sums (equations.hpp, "Surface
// tension"), for U(r) = -k m^2 W(max(r, d)) on the rest lattice (cubic,
// spacing d, poly6 W):
//  * surface: the potentials of the pairs that a plane between two layers
//    separates, per unit area, halved, over k m^2: pulling the halves apart
//    takes k m^2 sum W per area = 2 sigma (two new surfaces), so
//    sigma = k m^2 S with S = sum W / (2 d^2) (1/m^5).
//  * stiffness: sum over an interior particle's neighbours of
//    |W''(r)| + 2 |W'(r)| / r (1/m^5): omega_max^2 = k m times it bounds
//    the largest eigenvalue of the force's Jacobian per unit mass
//    (Gershgorin over the pair Hessians), the explicit step's stiffness.
struct CohesionLattice {
    double surface = 0.0;
    double stiffness = 0.0;
    double topLayerDeficit = 0.0;  // sum W over the missing half seen by the outermost layer, 1/m^5
};

CohesionLattice cohesionLattice(const Poly6Kernel& w, double d) {
    const double h = w.h, c6 = w.coefficient;
    const int reach = static_cast<int>(std::ceil(h / d));
    auto W = [&](double r2) { return r2 < h * h ? c6 * std::pow(h * h - r2, 3) : 0.0; };
    CohesionLattice lattice;
    for (int above = 0; above <= reach; ++above)
        for (int below = 1; below <= reach; ++below)
            for (int a = -reach; a <= reach; ++a)
                for (int b = -reach; b <= reach; ++b) {
                    const double dz = (above + below) * d;
                    lattice.surface += W(a * a * d * d + b * b * d * d + dz * dz);
                }
    lattice.surface /= 2.0 * d * d;
    // The outermost layer's missing neighbours (the next layer misses none
    // for h = 2 d), per unit area.
    for (int below = 1; below <= reach; ++below)
        for (int a = -reach; a <= reach; ++a)
            for (int b = -reach; b <= reach; ++b)
                lattice.topLayerDeficit += W(a * a * d * d + b * b * d * d + below * below * d * d);
    lattice.topLayerDeficit /= d * d;
    for (int a = -reach; a <= reach; ++a)
        for (int b = -reach; b <= reach; ++b)
            for (int k = -reach; k <= reach; ++k) {
                const double r2 = (a * a + b * b + k * k) * d * d;
                if (r2 == 0.0 || r2 >= h * h) continue;
                const double r = std::sqrt(r2), q = h * h - r2;
                const double first = 6.0 * c6 * q * q * r;                                // |W'|
                const double second = std::fabs(-6.0 * c6 * q * q + 24.0 * c6 * q * r2);  // |W''|
                lattice.stiffness += second + 2.0 * first / r;
            }
    return lattice;
}

}  // namespace

SolverConstants SolverConstants::from(const SimulationParams& params) {
    SolverConstants c;
    c.h = params.kernelRadius();
    c.restDensity = params.fluid.restDensity;
    c.inverseRestDensity = 1.0f / c.restDensity;
    c.poly6 = Poly6Kernel::withRadius(c.h);
    c.spiky = SpikyKernel::withRadius(c.h);

    // Sum the kernels over the rest lattice (cubic, spacing 2r) seen by one
    // interior particle. The mass is chosen so that this lattice has exactly
    // rest density, so a resting block starts with zero constraint error.
    const double d = params.particleSpacing();
    const int reach = static_cast<int>(std::ceil(c.h / d));
    double kernelSum = 0.0;
    double gradientSquaredSum = 0.0;
    for (int a = -reach; a <= reach; ++a)
        for (int b = -reach; b <= reach; ++b)
            for (int k = -reach; k <= reach; ++k) {
                const Vec3 r{float(a * d), float(b * d), float(k * d)};
                kernelSum += c.poly6.value(lengthSquared(r));
                gradientSquaredSum += lengthSquared(c.spiky.gradient(r, length(r)));
            }
    c.particleMass = static_cast<float>(c.restDensity / kernelSum);
    const double gradScale = c.particleMass / double(c.restDensity);
    // sum_k |grad_k C_i|^2 = |sum_j grad W|^2 + sum_j |grad W|^2, scaled by (m/rho0)^2;
    // the first term vanishes on a symmetric lattice.
    c.restGradientSum = static_cast<float>(gradScale * gradScale * gradientSquaredSum);

    const SolverParams& s = params.solver;
    // Units trap (DESIGN.md): the paper's epsilon and s_corr k are relative to
    // the constraint's natural scale; multiply / divide by restGradientSum.
    c.relaxationEpsilon = s.relaxation * c.restGradientSum;
    c.scorrScale = -s.artificialPressure.k / c.restGradientSum;
    const float dq = s.artificialPressure.dq * c.h;
    c.scorrInverseWdq = 1.0f / c.poly6.value(dq * dq);
    c.scorrExponent = s.artificialPressure.n;
    c.overRelaxation = s.effectiveOverRelaxation();
    c.ownLambdaWeight = 1.0f - 2.0f * s.consistentCorrection;

    const float r = params.particleRadius;
    c.particleRadius = r;
    c.domain = params.domain;
    c.collisionBox = {params.domain.min + Vec3{r, r, r}, params.domain.max - Vec3{r, r, r}};
    c.wall = makeWallTable(c, params.particleRadius, params.particleSpacing());

    const float sigma = params.fluid.surfaceTension;
    c.cohesionScale = 0.0f;
    c.adhesionScale = 0.0f;
    c.cohesionMinDistance2 = static_cast<float>(d * d);
    const double core = kCoreDistance * d;
    c.cohesionCoreDistance2 = static_cast<float>(core * core);
    c.cohesionCoreDistance = static_cast<float>(core);
    // 2 coreScale r_c^2 = kCoreStrength x 2 (h^2 - d^2)^2 d.
    c.cohesionCoreScale = static_cast<float>(
        kCoreStrength * std::pow(double(c.h) * c.h - d * d, 2) * d / (core * core));
    c.surfaceDensity = 0.0f;
    c.surfaceTension = 0.0f;
    c.surfaceFloor = 0.0f;
    c.surfaceOffset = 0.0f;
    c.capillaryTimeStep = std::numeric_limits<float>::infinity();
    if (sigma > 0.0f) {
        const double m = c.particleMass;
        const CohesionLattice lattice = cohesionLattice(c.poly6, d);
        c.surfaceDensity = static_cast<float>((1.0 - kSurfaceDeficit) * c.restDensity);
        c.strandSpread2 = static_cast<float>(kStrandSpread * d * d);
        c.strandLength2 = static_cast<float>(kStrandLength * d * d);
        // The surface energy is epsilon times the density the surface layer
        // misses: splitting the lattice costs epsilon m topLayerDeficit per
        // area and side, so sigma = kCohesionCalibration epsilon m deficit.
        const double epsilon = kCohesionCalibration * sigma / (m * lattice.topLayerDeficit);
        c.cohesionScale = static_cast<float>(6.0 * double(c.poly6.coefficient) * epsilon);
        c.capillaryTimeStep =
            static_cast<float>(1.0 / std::sqrt(2.0 * epsilon * lattice.stiffness));
        // The pull at kCohesionPull of the derivation's, its core
        // (cohesionScale x cohesionCoreScale) and the substep kept (the
        // calibration ran at the full cohesion's substep).
        c.cohesionScale *= float(kCohesionPull);
        c.cohesionCoreScale /= float(kCohesionPull);
        c.surfaceTension = sigma;
        c.surfaceFloor = kSurfaceFloor / std::sqrt(c.cohesionMinDistance2);
        c.surfaceOffset = kSurfaceOffset * std::sqrt(c.cohesionMinDistance2);
        const double k = sigma / (m * m * lattice.surface);  // m^5 / (kg s^2)
        c.adhesionScale = static_cast<float>(6.0 * double(c.poly6.coefficient) * k * m);
        // The artificial pressure is a position correction per iteration: as
        // an acceleration it grows as 1 / dt^2, and at the capillary time
        // step it stiffens the water into a gel (a drop stopped oscillating,
        // docs/surface_tension.md). The cohesion keeps surface particles
        // apart itself (no pull within one spacing): s_corr is off.
        c.scorrScale = 0.0f;
    }
    return c;
}

}  // namespace pbf
