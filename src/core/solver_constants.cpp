#include "pbf/solver_constants.hpp"

#include <cmath>
#include <limits>
#include <numbers>

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
                    cohesionSum += c.cohesion.value(length(rij)) * depth / length(rij);
                }
        }
        table.kernelSum[sample] = static_cast<float>(kernelSum);
        table.gradientSum[sample] = static_cast<float>(gradientSum);
        table.cohesionSum[sample] = static_cast<float>(cohesionSum);
    }
    return table;
}

// Phi(r) = int_r^h C(s) ds of the cohesion kernel: the depth of the pair
// potential (U = -k m^2 Phi) at distance r, in closed form.
double cohesionPotential(const CohesionKernel& kernel, double r) {
    const double h = kernel.h;
    if (r >= h) return 0.0;
    // P' = (h - s)^3 s^3
    auto P = [h](double s) {
        return h * h * h * std::pow(s, 4) / 4.0 - 3.0 * h * h * std::pow(s, 5) / 5.0 +
               h * std::pow(s, 6) / 2.0 - std::pow(s, 7) / 7.0;
    };
    const double half = 0.5 * h;
    double integral = 0.0;
    if (r >= half) {
        integral = P(h) - P(r);
    } else {
        integral = (P(h) - P(half)) + 2.0 * (P(half) - P(r)) -
                   std::pow(h, 6) / 64.0 * (half - r);
    }
    return kernel.coefficient * integral;
}

// S: the cohesion potentials of the pairs that a plane between two layers
// of the rest lattice (cubic, spacing d) separates, per unit area, halved.
// Pulling the halves apart takes k m^2 sum Phi per area = 2 sigma (two new
// surfaces), so sigma = k m^2 S. The discrete sum is used, not the
// continuum's (pi n^2 / 8) int r^4 C(r) dr (Kirkwood-Buff; 31 % larger for
// h = 2 d): a drop is made of particles on this lattice.
double latticeSurfaceSum(const CohesionKernel& kernel, double d) {
    const int reach = static_cast<int>(std::ceil(kernel.h / d));
    double sum = 0.0;
    for (int above = 0; above <= reach; ++above)
        for (int below = 1; below <= reach; ++below)
            for (int a = -reach; a <= reach; ++a)
                for (int b = -reach; b <= reach; ++b) {
                    const double dz = (above + below) * d;
                    sum += cohesionPotential(kernel, std::sqrt(a * a * d * d + b * b * d * d + dz * dz));
                }
    return sum / (2.0 * d * d);
}

}  // namespace

SolverConstants SolverConstants::from(const SimulationParams& params) {
    SolverConstants c;
    c.h = params.kernelRadius();
    c.restDensity = params.fluid.restDensity;
    c.inverseRestDensity = 1.0f / c.restDensity;
    c.poly6 = Poly6Kernel::withRadius(c.h);
    c.spiky = SpikyKernel::withRadius(c.h);
    c.cohesion = CohesionKernel::withRadius(c.h);

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
    c.overRelaxation = s.overRelaxation;

    const float r = params.particleRadius;
    c.particleRadius = r;
    c.domain = params.domain;
    c.collisionBox = {params.domain.min + Vec3{r, r, r}, params.domain.max - Vec3{r, r, r}};
    c.wall = makeWallTable(c, params.particleRadius, params.particleSpacing());

    const float sigma = params.fluid.surfaceTension;
    c.cohesionScale = 0.0f;
    c.capillaryTimeStep = std::numeric_limits<float>::infinity();
    if (sigma > 0.0f) {
        const double m = c.particleMass;
        c.cohesionScale = static_cast<float>(sigma / (m * latticeSurfaceSum(c.cohesion, d)));
        c.capillaryTimeStep = static_cast<float>(
            std::sqrt(double(c.restDensity) * d * d * d / (2.0 * std::numbers::pi * sigma)));
    }
    return c;
}

}  // namespace pbf
