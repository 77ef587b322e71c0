// The per-particle neighbour sums of Macklin & Mueller 2013, written once
// for any way of visiting a particle's neighbours (private header): the
// reference backend visits its neighbour lists (particle_sums.cpp), the GPU
// backend the sorted grid's stencil (backend/gpu). Each function evaluates
// one quantity for particle i from the terms of equations.hpp, in the
// plainest order: neighbours in the order visited, then the self term, then
// the walls and solids (backend/boundary.hpp).
//
// `neighbors(visit)` calls visit(j) for every neighbour j of particle i (j
// != i); the state is read through accessors x(j) (positions), lambda(j),
// v(j), rho(j), omega(j), so that arrays of Vec3 and structure-of-arrays
// device memory both fit. PBF_HD: the GPU kernels call these.
#pragma once

#include <cstddef>
#include <cstdint>

#include "backend/boundary.hpp"
#include "backend/reference/equations.hpp"
#include "pbf/core/config.hpp"
#include "pbf/core/solver_constants.hpp"
#include "pbf/core/vec3.hpp"

namespace pbf::reference {

struct DensityAndLambda {
    float density = 0.0f;  // rho_i, eq. 2
    float lambda = 0.0f;   // lambda_i, eq. 11
};

// The walls' and solids' kernel sum and its gradient at x (backend/boundary.hpp).
struct BoundaryTerms {
    float kernelSum = 0.0f;
    Vec3 gradient;
};

template <class Solids>
PBF_HD BoundaryTerms boundaryTerms(const SolverConstants& c, const Solids* solids, const Vec3& x) {
    BoundaryTerms b;
    boundary::addWallContribution(c, x, b.kernelSum, b.gradient);
    boundary::addSolidContribution(c, solids, x, b.kernelSum, b.gradient);
    return b;
}

// Eq. 1-2 and 8-11 at the positions x (the current x*); `solids` may be null.
template <class Solids, class Neighbors, class Positions>
PBF_HD DensityAndLambda densityAndLambdaOf(const SolverConstants& c, const Solids* solids,
                                           const Neighbors& neighbors, const Positions& x,
                                           std::uint32_t i) {
    const Vec3 xi = x(i);
    float density = 0.0f;
    Vec3 gradientI{};                      // grad_{x_i} C_i (eq. 8, k = i)
    float neighborGradientSquared = 0.0f;  // sum_j |grad_{x_j} C_i|^2 (eq. 8, k = j)
    neighbors([&](std::uint32_t j) {
        const Vec3 rij = xi - x(j);
        density += densityTerm(c, rij);
        gradientI += constraintGradientOfSelfTerm(c, rij);
        neighborGradientSquared += lengthSquared(constraintGradientOfNeighbor(c, rij));
    });
    density += selfDensity(c);
    // The walls and solids are fixed: they add to rho_i and grad_i C_i only.
    const BoundaryTerms b = boundaryTerms(c, solids, xi);
    density += boundaryDensity(c, b.kernelSum);
    gradientI += boundaryConstraintGradient(c, b.gradient);

    const float gradientSquaredSum = lengthSquared(gradientI) + neighborGradientSquared;
    return {density, lambda(c, densityConstraint(c, density), gradientSquaredSum)};
}

// Eq. 12-14: dp_i from the lambdas of particle i and its neighbours.
template <class Solids, class Neighbors, class Positions, class Lambdas>
PBF_HD Vec3 positionCorrectionOf(const SolverConstants& c, const Solids* solids,
                                 const Neighbors& neighbors, const Positions& x,
                                 const Lambdas& lambdas, std::uint32_t i) {
    const Vec3 xi = x(i);
    const float lambdaI = lambdas(i);
    Vec3 dp{};
    neighbors(
        [&](std::uint32_t j) { dp += positionCorrectionTerm(c, lambdaI, lambdas(j), xi - x(j)); });
    dp += boundaryPositionCorrection(c, lambdaI, boundaryTerms(c, solids, xi).gradient);
    return dp;
}

// The part of eq. 14 that the nearest solid contributes at x_i (it carries
// no lambda: lambda_i (m/rho0) times its share of grad_i C_i) and which solid
// that is (boundary::kNoSolid and zero when none is in reach): the move
// whose reaction a coupled solid feels.
struct SolidCorrection {
    std::size_t solid = 0;
    Vec3 displacement;
};

template <class Solids>
PBF_HD SolidCorrection solidCorrectionOf(const SolverConstants& c, const Solids& solids,
                                         float lambdaI, const Vec3& xi) {
    const boundary::SolidContribution s = boundary::solidContribution(c, solids, xi);
    return {s.solid, boundaryPositionCorrection(c, lambdaI, s.gradient)};
}

// Eq. 17: v_i after XSPH viscosity, from the velocities v and densities rho
// of the state before XSPH (Jacobi: no neighbour has been updated yet).
template <class Neighbors, class Positions, class Velocities, class Densities>
PBF_HD Vec3 xsphVelocityOf(const SolverConstants& c, float viscosity, const Neighbors& neighbors,
                           const Positions& x, const Velocities& v, const Densities& rho,
                           std::uint32_t i) {
    const Vec3 xi = x(i), vi = v(i);
    const float rhoI = rho(i);
    Vec3 dv{};
    neighbors(
        [&](std::uint32_t j) { dv += xsphTerm(c, viscosity, xi - x(j), vi, v(j), rhoI, rho(j)); });
    return vi + dv;
}

// Eq. 15: the vorticity omega_i, from the same state as xsphVelocityOf.
template <class Neighbors, class Positions, class Velocities, class Densities>
PBF_HD Vec3 vorticityOf(const SolverConstants& c, const Neighbors& neighbors, const Positions& x,
                        const Velocities& v, const Densities& rho, std::uint32_t i) {
    const Vec3 xi = x(i), vi = v(i);
    Vec3 omega{};
    neighbors([&](std::uint32_t j) { omega += vorticityTerm(c, xi - x(j), vi, v(j), rho(j)); });
    return omega;
}

// Eq. 16: eta_i = grad |omega| at x_i (SPH difference form).
template <class Neighbors, class Positions, class Vorticities, class Densities>
PBF_HD Vec3 vorticityGradientOf(const SolverConstants& c, const Neighbors& neighbors,
                                const Positions& x, const Vorticities& omega, const Densities& rho,
                                std::uint32_t i) {
    const Vec3 xi = x(i);
    const float magnitudeI = length(omega(i));
    Vec3 eta{};
    neighbors([&](std::uint32_t j) {
        eta += vorticityGradientTerm(c, xi - x(j), magnitudeI, length(omega(j)), rho(j));
    });
    return eta;
}

// The physical viscosity's acceleration a_i = nu lap v_i (equations.hpp,
// viscosityTerm, normalised by viscosityMomentTerm): the neighbours, then
// for each domain wall in reach the mirror images of i and of its
// neighbours (free slip). From the velocities v and densities rho before
// XSPH (Jacobi), like xsphVelocityOf. `neighbors` is visited once plus once
// per wall in reach.
template <class Neighbors, class Positions, class Velocities, class Densities>
PBF_HD Vec3 viscosityAccelerationOf(const SolverConstants& c, float nu, const Neighbors& neighbors,
                                    const Positions& x, const Velocities& v, const Densities& rho,
                                    std::uint32_t i) {
    const Vec3 xi = x(i), vi = v(i);
    const float rhoI = rho(i);
    Vec3 a{};
    float moment = 0.0f;
    neighbors([&](std::uint32_t j) {
        a += viscosityTerm(c, nu, xi - x(j), vi, v(j), rhoI, rho(j));
        moment += viscosityMomentTerm(c, xi - x(j), rhoI, rho(j));
    });
    for (int axis = 0; axis < 3; ++axis)
        for (int side = -1; side <= 1; side += 2) {
            if (!wallInReach(c, xi, axis, side)) continue;
            const float plane = wallPlane(c, axis, side);
            const Vec3 self = xi - mirrored(xi, axis, plane);
            a += viscosityTerm(c, nu, self, vi, mirroredVelocity(vi, axis), rhoI, rhoI);
            moment += viscosityMomentTerm(c, self, rhoI, rhoI);
            neighbors([&](std::uint32_t j) {
                const Vec3 rij = xi - mirrored(x(j), axis, plane);
                a += viscosityTerm(c, nu, rij, vi, mirroredVelocity(v(j), axis), rhoI, rho(j));
                moment += viscosityMomentTerm(c, rij, rhoI, rho(j));
            });
        }
    return normalisedViscosity(a, moment);
}

// The spread of particle i's neighbours at the positions x (SpreadSums,
// self included).
template <class Neighbors, class Positions>
PBF_HD SpreadSums spreadOf(const SolverConstants& c, const Neighbors& neighbors, const Positions& x,
                           std::uint32_t i) {
    const Vec3 xi = x(i);
    SpreadSums spread;
    neighbors([&](std::uint32_t j) { addSpreadTerm(c, xi - x(j), spread); });
    addSpreadTerm(c, Vec3{}, spread);
    return spread;
}

// s_i, particle i's weight in the surface layer: 1 on the surface
// (onSurface) unless its neighbours' spread at the positions x (the
// end-of-step x*) makes it a strand (inStrand) that no wall or solid within
// reach holds; 0 otherwise. `solids` may be null; the boundary is looked up
// for strands only.
template <class Solids, class Neighbors, class Positions>
PBF_HD float surfaceLayerOf(const SolverConstants& c, const Solids* solids,
                            const Neighbors& neighbors, const Positions& x, float density,
                            std::uint32_t i) {
    if (!onSurface(c, density)) return 0.0f;
    if (!inStrand(c, spreadOf(c, neighbors, x, i))) return 1.0f;
    const Vec3 xi = x(i);
    float boundarySum = 0.0f;
    Vec3 boundaryGradient;
    boundary::addWallContribution(c, xi, boundarySum, boundaryGradient);
    boundary::addSolidContribution(c, solids, xi, boundarySum, boundaryGradient);
    return boundarySum > 0.0f ? 1.0f : 0.0f;
}

// Surface tension's acceleration of particle i at the positions x (the
// end-of-step x*) with the surface layer's weights s (surfaceLayerOf): the
// cohesion of the surface layer (cohesionTerm) plus the walls' and the nearest solid's adhesion
// (boundary::adhesionPull, adhesionAcceleration); `solidAcceleration` is the
// solid's part (its reaction acts on a coupled solid) and `solid` which one
// (boundary::kNoSolid: none). `solids` may be null.
struct SurfaceTensionAcceleration {
    Vec3 total;
    Vec3 solidAcceleration;
    std::size_t solid = boundary::kNoSolid;
};
template <class Solids, class Neighbors, class Positions, class LayerWeights>
PBF_HD SurfaceTensionAcceleration surfaceTensionOf(const SolverConstants& c, float wallAdhesion,
                                                   const Solids* solids, const Neighbors& neighbors,
                                                   const Positions& x, const LayerWeights& s,
                                                   std::uint32_t i) {
    const Vec3 xi = x(i);
    const bool surfaceI = s(i) > 0.0f;
    Vec3 cohesion{};
    neighbors(
        [&](std::uint32_t j) { cohesion += cohesionTerm(c, xi - x(j), surfaceI, s(j) > 0.0f); });
    const boundary::AdhesionPull pull = boundary::adhesionPull(c, wallAdhesion, solids, xi);
    SurfaceTensionAcceleration a;
    a.solidAcceleration = adhesionAcceleration(c, pull.solid);
    a.total = cohesion + adhesionAcceleration(c, pull.walls) + a.solidAcceleration;
    a.solid = pull.solidIndex;
    return a;
}

// The curvature force (equations.hpp, "Curvature force"), in four passes
// over the positions x (the end-of-step x*), each reading the previous
// pass's field at the neighbours: g, the band's averaged normals nb, kappa,
// then the force. Every particle's field is computed before the next pass
// (on MPI the ghosts' come from their owners between the passes).

// g_i = sum_j colourGradientTerm.
template <class Neighbors, class Positions>
PBF_HD Vec3 colourGradientOf(const SolverConstants& c, const Neighbors& neighbors,
                             const Positions& x, std::uint32_t i) {
    const Vec3 xi = x(i);
    Vec3 g{};
    neighbors([&](std::uint32_t j) { g += colourGradientTerm(c, xi - x(j)); });
    return g;
}

// nb_i: the band neighbours' normals averaged (weights W A, the particle's
// own left out; its own n where no neighbour is on the band); 0 off the band.
template <class Neighbors, class Positions, class Gradients>
PBF_HD Vec3 bandNormalOf(const SolverConstants& c, const Neighbors& neighbors, const Positions& x,
                         const Gradients& g, std::uint32_t i) {
    const Vec3 gi = g(i);
    if (!(surfaceBandWeight(c, gi) > 0.0f)) return {};
    const Vec3 xi = x(i);
    Vec3 sum{};
    neighbors([&](std::uint32_t j) {
        const Vec3 gj = g(j);
        if (surfaceBandWeight(c, gj) > 0.0f) sum += bandNormalTerm(c, xi - x(j), gj);
    });
    const float length2 = lengthSquared(sum);
    return length2 > 0.0f ? sum * (1.0f / std::sqrt(length2)) : outwardNormal(gi);
}

// kappa_i (1/m) from the band neighbours' nb; 0 off the band.
template <class Neighbors, class Positions, class Gradients, class Normals>
PBF_HD float curvatureOf(const SolverConstants& c, const Neighbors& neighbors, const Positions& x,
                         const Gradients& g, const Normals& nb, std::uint32_t i) {
    if (!(surfaceBandWeight(c, g(i)) > 0.0f)) return 0.0f;
    const Vec3 xi = x(i);
    const Vec3 nbI = nb(i);
    CurvatureSums sums;
    neighbors([&](std::uint32_t j) {
        if (surfaceBandWeight(c, g(j)) > 0.0f) addCurvatureTerm(c, xi - x(j), nbI, nb(j), sums);
    });
    return curvatureOf(sums);
}

// dt a_i: kappa averaged over the band (weights W A, self included), the
// column sum D_i, then curvatureForceVelocityChange; 0 off the band.
template <class Neighbors, class Positions, class Gradients, class Curvatures>
PBF_HD Vec3 curvatureForceVelocityChangeOf(const SolverConstants& c, float dt,
                                           const Neighbors& neighbors, const Positions& x,
                                           const Gradients& g, const Curvatures& kappa,
                                           std::uint32_t i) {
    const Vec3 gi = g(i);
    const float weightI = surfaceBandWeight(c, gi);
    if (!(weightI > 0.0f)) return {};
    const Vec3 xi = x(i);
    const Vec3 ni = outwardNormal(gi);
    const float volume = c.particleMass / c.restDensity;
    float kappaSum = c.poly6.value(0.0f) * weightI * kappa(i);
    float kappaWeight = c.poly6.value(0.0f) * weightI;
    float column = volume * weightI * columnWeight(c, Vec3{}, ni);
    neighbors([&](std::uint32_t j) {
        const float weightJ = surfaceBandWeight(c, g(j));
        if (!(weightJ > 0.0f)) return;
        const Vec3 rij = xi - x(j);
        const float w = c.poly6.value(lengthSquared(rij)) * weightJ;
        kappaSum += w * kappa(j);
        kappaWeight += w;
        column += volume * weightJ * columnWeight(c, rij, ni);
    });
    return curvatureForceVelocityChange(c, dt, gi, kappaSum / kappaWeight, column);
}

}  // namespace pbf::reference
