// The neighbour sums of the reference backend, one particle at a time
// (private header): the sums of neighbor_sums.hpp over the reference's
// neighbour lists and arrays of Vec3. The backend calls them for every
// particle; the tests call them to compare the SIMD passes with the paper.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "backend/reference/neighbor_sums.hpp"
#include "pbf/core/solver_constants.hpp"
#include "pbf/core/vec3.hpp"
#include "pbf/geometry/solids.hpp"

namespace pbf::reference {

using NeighborIndices = std::span<const std::uint32_t>;

// Eq. 1-2 and 8-11 at the positions x (the current x*); `solids` may be null.
DensityAndLambda densityAndLambda(const SolverConstants& c, const SolidSet* solids,
                                  std::span<const Vec3> x, NeighborIndices neighbors,
                                  std::size_t i);

// Eq. 12-14: dp_i from the lambdas of particle i and its neighbours.
Vec3 positionCorrection(const SolverConstants& c, const SolidSet* solids, std::span<const Vec3> x,
                        std::span<const float> lambdas, NeighborIndices neighbors, std::size_t i);

// solidCorrectionOf (neighbor_sums.hpp) for the host's solids.
SolidCorrection solidCorrection(const SolverConstants& c, const SolidSet& solids, float lambdaI,
                                const Vec3& xi);

// Eq. 17: v_i after XSPH viscosity, from the velocities v and densities rho
// of the state before XSPH (Jacobi: no neighbour has been updated yet).
Vec3 xsphVelocity(const SolverConstants& c, float viscosity, std::span<const Vec3> x,
                  std::span<const Vec3> v, std::span<const float> rho, NeighborIndices neighbors,
                  std::size_t i);

// The physical viscosity's acceleration a_i = nu lap v_i
// (viscosityAccelerationOf: the neighbours, then the domain walls' mirror images).
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

// The middle and largest eigenvalues of the spread of particle i's
// neighbours (m^2; spreadOf, spreadAxes): a strand has the middle below
// SolverConstants::strandSpread2 and the largest above strandLength2.
SpreadAxes spreadAxes(const SolverConstants& c, std::span<const Vec3> x, NeighborIndices neighbors,
                      std::size_t i);

// s_i, particle i's weight in the surface layer at the positions x (the
// end-of-step x*) with its density rho_i (surfaceLayerOf); `solids` may be null.
float surfaceLayer(const SolverConstants& c, const SolidSet* solids, std::span<const Vec3> x,
                   float density, NeighborIndices neighbors, std::size_t i);

// Surface tension's acceleration of particle i at the positions x (the
// end-of-step x*) with the surface layer's weights s (surfaceTensionOf);
// `solids` may be null.
SurfaceTensionAcceleration surfaceTension(const SolverConstants& c, float wallAdhesion,
                                          const SolidSet* solids, std::span<const Vec3> x,
                                          std::span<const float> s, NeighborIndices neighbors,
                                          std::size_t i);

// The curvature force's four passes at the positions x (neighbor_sums.hpp):
// g_i, the band's averaged normal nb_i, kappa_i, and the velocity change
// dt a_i (dt = 1: a_i), each from the previous pass's field of all particles.
Vec3 colourGradient(const SolverConstants& c, std::span<const Vec3> x, NeighborIndices neighbors,
                    std::size_t i);
Vec3 bandNormal(const SolverConstants& c, std::span<const Vec3> x, std::span<const Vec3> g,
                NeighborIndices neighbors, std::size_t i);
float curvature(const SolverConstants& c, std::span<const Vec3> x, std::span<const Vec3> g,
                std::span<const Vec3> nb, NeighborIndices neighbors, std::size_t i);
Vec3 curvatureForceVelocityChange(const SolverConstants& c, float dt, std::span<const Vec3> x,
                                  std::span<const Vec3> g, std::span<const float> kappa,
                                  NeighborIndices neighbors, std::size_t i);

}  // namespace pbf::reference
