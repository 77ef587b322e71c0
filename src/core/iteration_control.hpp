// How many Jacobi density iterations a substep runs (private header, shared
// by the backends): `solver.iterations`, or — error-controlled, as
// SPlisHSPlasH's maxError — until the average compression the density pass
// measures is at most `solver.max_density_error`, between
// `solver.min_iterations` and `solver.max_iterations` corrections.
//
// The check costs nothing extra: the density pass already has every
// particle's constraint C_i = max(rho_i/rho0 - 1, 0); their sum is reduced
// per block, in block order (deterministic under any thread count).
#pragma once

#include "pbf/params.hpp"

namespace pbf {

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
