#include "backend/cpu/cpu_backend.hpp"

#include <algorithm>

namespace pbf {

void CpuBackend::step(const SolverContext& context, float dt) {
    reactions_.reset(store_.size(), context.solids);
    solver_.step(context, store_, dt, times_, reactions_.active() ? &reactions_ : nullptr);
    reactions_.forces(context.constants.particleMass, dt, lastReactions_);
}

BackendDiagnostics CpuBackend::diagnostics() const {
    BackendDiagnostics d;
    const NeighborSearch& search = solver_.neighborSearch();
    const double n = double(std::max<std::size_t>(1, store_.size()));
    d.memoryBytes = store_.memoryBytes() + solver_.memoryBytes();
    d.neighborsPerParticle = double(search.totalNeighborCount()) / n;
    d.compactListShare =
        double(search.compactBlockCount()) / double(std::max<std::size_t>(1, search.blockCount()));
    return d;
}

}  // namespace pbf
