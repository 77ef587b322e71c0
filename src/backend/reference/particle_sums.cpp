#include "backend/reference/particle_sums.hpp"

#include "backend/boundary.hpp"
#include "backend/reference/equations.hpp"

namespace pbf::reference {
namespace {

// The walls' and solids' kernel sum and its gradient at x (backend/boundary.hpp).
struct BoundaryTerms {
    float kernelSum = 0.0f;
    Vec3 gradient;
};

BoundaryTerms boundaryTerms(const SolverConstants& c, const SolidSet* solids, const Vec3& x) {
    BoundaryTerms b;
    boundary::addWallContribution(c, x, b.kernelSum, b.gradient);
    boundary::addSolidContribution(c, solids, x, b.kernelSum, b.gradient);
    return b;
}

}  // namespace

DensityAndLambda densityAndLambda(const SolverConstants& c, const SolidSet* solids,
                                  std::span<const Vec3> x, NeighborIndices neighbors,
                                  std::size_t i) {
    const Vec3 xi = x[i];
    float density = 0.0f;
    Vec3 gradientI{};                      // grad_{x_i} C_i (eq. 8, k = i)
    float neighborGradientSquared = 0.0f;  // sum_j |grad_{x_j} C_i|^2 (eq. 8, k = j)
    for (const std::uint32_t j : neighbors) {
        const Vec3 rij = xi - x[j];
        density += densityTerm(c, rij);
        gradientI += constraintGradientOfSelfTerm(c, rij);
        neighborGradientSquared += lengthSquared(constraintGradientOfNeighbor(c, rij));
    }
    density += selfDensity(c);
    // The walls and solids are fixed: they add to rho_i and grad_i C_i only.
    const BoundaryTerms b = boundaryTerms(c, solids, xi);
    density += boundaryDensity(c, b.kernelSum);
    gradientI += boundaryConstraintGradient(c, b.gradient);

    const float gradientSquaredSum = lengthSquared(gradientI) + neighborGradientSquared;
    return {density, lambda(c, densityConstraint(c, density), gradientSquaredSum)};
}

Vec3 positionCorrection(const SolverConstants& c, const SolidSet* solids, std::span<const Vec3> x,
                        std::span<const float> lambdas, NeighborIndices neighbors, std::size_t i) {
    const Vec3 xi = x[i];
    Vec3 dp{};
    for (const std::uint32_t j : neighbors)
        dp += positionCorrectionTerm(c, lambdas[i], lambdas[j], xi - x[j]);
    dp += boundaryPositionCorrection(c, lambdas[i], boundaryTerms(c, solids, xi).gradient);
    return dp;
}

SolidCorrection solidCorrection(const SolverConstants& c, const SolidSet& solids, float lambdaI,
                                const Vec3& xi) {
    const boundary::SolidContribution s = boundary::solidContribution(c, solids, xi);
    return {s.solid, boundaryPositionCorrection(c, lambdaI, s.gradient)};
}

Vec3 xsphVelocity(const SolverConstants& c, float viscosity, std::span<const Vec3> x,
                  std::span<const Vec3> v, std::span<const float> rho, NeighborIndices neighbors,
                  std::size_t i) {
    Vec3 dv{};
    for (const std::uint32_t j : neighbors)
        dv += xsphTerm(c, viscosity, x[i] - x[j], v[i], v[j], rho[i], rho[j]);
    return v[i] + dv;
}

Vec3 viscosityAcceleration(const SolverConstants& c, float nu, std::span<const Vec3> x,
                           std::span<const Vec3> v, std::span<const float> rho,
                           NeighborIndices neighbors, std::size_t i) {
    Vec3 a{};
    float moment = 0.0f;
    for (const std::uint32_t j : neighbors) {
        a += viscosityTerm(c, nu, x[i] - x[j], v[i], v[j], rho[i], rho[j]);
        moment += viscosityMomentTerm(c, x[i] - x[j], rho[i], rho[j]);
    }
    for (int axis = 0; axis < 3; ++axis)
        for (const int side : {-1, 1}) {
            if (!wallInReach(c, x[i], axis, side)) continue;
            const float plane = wallPlane(c, axis, side);
            const Vec3 self = x[i] - mirrored(x[i], axis, plane);
            a += viscosityTerm(c, nu, self, v[i], mirroredVelocity(v[i], axis), rho[i], rho[i]);
            moment += viscosityMomentTerm(c, self, rho[i], rho[i]);
            for (const std::uint32_t j : neighbors) {
                const Vec3 rij = x[i] - mirrored(x[j], axis, plane);
                a += viscosityTerm(c, nu, rij, v[i], mirroredVelocity(v[j], axis), rho[i], rho[j]);
                moment += viscosityMomentTerm(c, rij, rho[i], rho[j]);
            }
        }
    return normalisedViscosity(a, moment);
}

Vec3 vorticity(const SolverConstants& c, std::span<const Vec3> x, std::span<const Vec3> v,
               std::span<const float> rho, NeighborIndices neighbors, std::size_t i) {
    Vec3 omega{};
    for (const std::uint32_t j : neighbors)
        omega += vorticityTerm(c, x[i] - x[j], v[i], v[j], rho[j]);
    return omega;
}

Vec3 vorticityGradient(const SolverConstants& c, std::span<const Vec3> x,
                       std::span<const Vec3> omega, std::span<const float> rho,
                       NeighborIndices neighbors, std::size_t i) {
    const float magnitudeI = length(omega[i]);
    Vec3 eta{};
    for (const std::uint32_t j : neighbors)
        eta += vorticityGradientTerm(c, x[i] - x[j], magnitudeI, length(omega[j]), rho[j]);
    return eta;
}

SurfaceTensionAcceleration surfaceTension(const SolverConstants& c, float wallAdhesion,
                                          const SolidSet* solids, std::span<const Vec3> x,
                                          std::span<const float> rho, NeighborIndices neighbors,
                                          std::size_t i) {
    SurfaceTensionAcceleration a;
    const bool surfaceI = onSurface(c, rho[i]);
    Vec3 cohesion{};
    for (const std::uint32_t j : neighbors)
        cohesion += cohesionTerm(c, x[i] - x[j], surfaceI, onSurface(c, rho[j]));
    const boundary::AdhesionPull pull = boundary::adhesionPull(c, wallAdhesion, solids, x[i]);
    a.solidAcceleration = adhesionAcceleration(c, pull.solid);
    a.total = cohesion + adhesionAcceleration(c, pull.walls) + a.solidAcceleration;
    a.solid = pull.solidIndex;
    return a;
}

}  // namespace pbf::reference
