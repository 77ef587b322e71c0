// How many Jacobi density iterations a substep runs (private header, shared
// by the backends): `solver.iterations`, or — error-controlled, as
// SPlisHSPlasH's maxError — until the average compression the density pass
// measures is at most `solver.max_density_error`, between
// `solver.min_iterations` and `solver.max_iterations` corrections.
//
// The check costs nothing extra: the density pass already has every
// particle's constraint C_i = max(rho_i/rho0 - 1, 0); their sum is reduced
// per block in fixed point (fixedPointCompression: the same bits under any
// thread or rank count).
#pragma once

#include <cstdint>

#include "pbf/core/config.hpp"
#include "pbf/core/params.hpp"

namespace pbf {

// C_i in fixed point (units of 2^-32) for the stopping test's sum. Integer
// sums do not depend on their order, so the test sees the same bits on any
// thread count and on any number of MPI ranks (a float sum would not: the
// ranks hold different particles). The multiply by a power of two is exact;
// the truncation loses under 2.4e-10 per particle. int64 holds the sum of
// 2^31 particles at C = 1, far beyond any real state.
PBF_HD inline std::int64_t fixedPointCompression(float constraint) {
    return static_cast<std::int64_t>(constraint * 0x1p32f);
}
inline double averageCompression(std::int64_t fixedPointSum, std::uint64_t particles) {
    return particles > 0 ? double(fixedPointSum) * 0x1p-32 / double(particles) : 0.0;
}

class IterationControl {
  public:
    explicit IterationControl(const SolverParams& s)
        : tolerance_(s.maxDensityError),
          minimum_(s.maxDensityError > 0.0f ? s.minIterations : s.iterations),
          maximum_(s.maxDensityError > 0.0f ? s.maxIterations : s.iterations) {}

    bool errorControlled() const { return tolerance_ > 0.0f; }
    // Corrections to run at most. Each follows a density pass; as in Alg. 1,
    // no density pass follows the last one (fixed mode: exactly `iterations`).
    int maxIterations() const { return maximum_; }
    // After the density pass that follows `corrections` corrections: is the
    // state good enough to stop without correcting again?
    bool converged(int corrections, double averageCompression) const {
        return errorControlled() && corrections >= minimum_ && averageCompression <= tolerance_;
    }

  private:
    float tolerance_;
    int minimum_;
    int maximum_;
};

}  // namespace pbf
