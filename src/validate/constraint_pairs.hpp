// The density constraint's force, split pair by pair (the laplace case,
// src/validate/laplace.cpp).
//
// PBF records each particle's total correction of a substep (the solve
// acceleration, warm start on), not its pair terms. Eq. 14 of Macklin &
// Mueller 2013 makes every correction a sum of equal and opposite pair
// terms, Delta x_i = (1 / rho0) sum_j (lambda_i + lambda_j) grad W(x_i - x_j),
// so one L_i per particle is fitted to the recorded accelerations,
//   a_i ~ sum_j (L_i + L_j) grad W_spiky(x_i - x_j),
// by least squares, and the pair force of i and j is m (L_i + L_j) grad W.
// The fit is not exact: the substep's iterations moved the particles between
// their lambdas, and the warm start adds its share; `residual` says how far
// off (|A L - a| / |a|).
#pragma once

#include <cstdint>
#include <vector>

#include "pbf/core/kernels.hpp"
#include "pbf/core/vec3.hpp"

namespace pbf::validation::detail {

struct ConstraintPairs {
    std::vector<double> L;  // per particle, m^5/s^2: a_i = sum_j (L_i + L_j) grad W_ij
    double residual = 0.0;  // |A L - a| / |a|
};

// `neighbours[i]`: the particles j != i within the kernel radius of i (both
// directions listed). Conjugate gradients on the normal equations (CGLS;
// Hestenes & Stiefel 1952), at most `iterations`.
ConstraintPairs fitConstraintPairs(const std::vector<Vec3>& x, const std::vector<Vec3>& a,
                                   const std::vector<std::vector<std::uint32_t>>& neighbours,
                                   const SpikyKernel& kernel, int iterations = 300);

}  // namespace pbf::validation::detail
