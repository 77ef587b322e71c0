// The neighbour sums of the reference backend, one particle at a time
// (private header): each function evaluates one quantity of Macklin &
// Mueller 2013 for particle i from the terms of equations.hpp, in the
// plainest order (neighbours in list order, then the self term, then the
// walls and solids). The backend calls them for every particle; the tests
// call them to compare the SIMD passes with the paper.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "pbf/core/solver_constants.hpp"
#include "pbf/core/vec3.hpp"
#include "pbf/geometry/solids.hpp"

namespace pbf::reference {

using NeighborIndices = std::span<const std::uint32_t>;

struct DensityAndLambda {
    float density = 0.0f;  // rho_i, eq. 2
    float lambda = 0.0f;   // lambda_i, eq. 11
};

// Eq. 1-2 and 8-11 at the positions x (the current x*); `solids` may be null.
DensityAndLambda densityAndLambda(const SolverConstants& c, const SolidSet* solids,
                                  std::span<const Vec3> x, NeighborIndices neighbors,
                                  std::size_t i);

// Eq. 12-14: dp_i from the lambdas of particle i and its neighbours.
Vec3 positionCorrection(const SolverConstants& c, const SolidSet* solids, std::span<const Vec3> x,
                        std::span<const float> lambdas, NeighborIndices neighbors, std::size_t i);

// The part of eq. 14 that the nearest solid contributes at x_i (it carries
// no lambda: lambda_i (m/rho0) times its share of grad_i C_i) and which solid
// that is (boundary::kNoSolid and zero when none is in reach): the move
// whose reaction a coupled solid feels.
struct SolidCorrection {
    std::size_t solid = 0;
    Vec3 displacement;
};
SolidCorrection solidCorrection(const SolverConstants& c, const SolidSet& solids, float lambdaI,
                                const Vec3& xi);

// Eq. 17: v_i after XSPH viscosity, from the velocities v and densities rho
// of the state before XSPH (Jacobi: no neighbour has been updated yet).
Vec3 xsphVelocity(const SolverConstants& c, float viscosity, std::span<const Vec3> x,
                  std::span<const Vec3> v, std::span<const float> rho, NeighborIndices neighbors,
                  std::size_t i);

// The physical viscosity's acceleration a_i = nu lap v_i
// (equations.hpp, viscosityTerm, normalised by viscosityMomentTerm): the
// neighbours, then for each domain wall in reach the mirror images of i and
// of its neighbours.
Vec3 viscosityAcceleration(const SolverConstants& c, float nu, std::span<const Vec3> x,
                           std::span<const Vec3> v, std::span<const float> rho,
                           NeighborIndices neighbors, std::size_t i);

// Eq. 15: the vorticity omega_i, from the same state as xsphVelocity.
Vec3 vorticity(const SolverConstants& c, std::span<const Vec3> x, std::span<const Vec3> v,
               std::span<const float> rho, NeighborIndices neighbors, std::size_t i);

// Eq. 16: eta_i = grad |omega| at x_i (SPH difference form).
Vec3 vorticityGradient(const SolverConstants& c, std::span<const Vec3> x,
                       std::span<const Vec3> omega, std::span<const float> rho,
                       NeighborIndices neighbors, std::size_t i);

// Surface tension's acceleration of particle i at the positions x (the
// end-of-step x*) with the densities rho: the cohesion of the surface
// layer plus the walls' and the nearest solid's adhesion;
// `solidAcceleration` is the solid's part (its reaction acts on a coupled
// solid) and `solid` which one (boundary::kNoSolid: none).
struct SurfaceTensionAcceleration {
    Vec3 total;
    Vec3 solidAcceleration;
    std::size_t solid = 0;
};
SurfaceTensionAcceleration surfaceTension(const SolverConstants& c, float wallAdhesion,
                                          const SolidSet* solids, std::span<const Vec3> x,
                                          std::span<const float> rho, NeighborIndices neighbors,
                                          std::size_t i);

}  // namespace pbf::reference
