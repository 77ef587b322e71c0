#include "pbf/core/solver_constants.hpp"

#include <cmath>

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
        double kernelSum = 0.0, gradientSum = 0.0;
        for (int layer = 0; s + radius + layer * spacing < c.h; ++layer) {
            const double depth = s + radius + layer * spacing;  // normal distance to the layer
            for (int a = -reach; a <= reach; ++a)
                for (int b = -reach; b <= reach; ++b) {
                    const Vec3 rij{float(a * spacing), float(b * spacing), float(depth)};
                    kernelSum += c.poly6.value(lengthSquared(rij));
                    gradientSum -= c.spiky.gradient(rij, length(rij)).z;  // component into the wall
                }
        }
        table.kernelSum[sample] = static_cast<float>(kernelSum);
        table.gradientSum[sample] = static_cast<float>(gradientSum);
    }
    return table;
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
    c.overRelaxation = s.overRelaxation;

    const float r = params.particleRadius;
    c.particleRadius = r;
    c.domain = params.domain;
    c.collisionBox = {params.domain.min + Vec3{r, r, r}, params.domain.max - Vec3{r, r, r}};
    c.wall = makeWallTable(c, params.particleRadius, params.particleSpacing());
    return c;
}

}  // namespace pbf
