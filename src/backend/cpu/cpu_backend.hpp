// The CPU backend (private header): particles in host memory, the SIMD
// solver (backend/cpu/solver.hpp), OpenMP threads; deterministic.
#pragma once

#include <memory>

#include "backend/cpu/solver.hpp"
#include "backend/host_backend.hpp"

namespace pbf {

class CpuBackend final : public HostBackend {
  public:
    CpuBackend(const SimulationParams& params, const BackendOptions& options)
        : solver_(params.domain, params.kernelRadius(), options.compactListSpan) {}

    BackendKind kind() const override { return BackendKind::Cpu; }
    void step(const SolverContext& context, float dt) override;
    BackendDiagnostics diagnostics() const override;

    const Solver& solver() const { return solver_; }

  private:
    Solver solver_;
};

}  // namespace pbf
