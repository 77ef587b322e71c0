// The distributed backend (private header): the CPU solver on one slab of
// the sorted grid per MPI rank (backend/mpi/slab_halo.hpp does the
// decomposition, migration and halos; backend/cpu/solver.hpp the work).
#pragma once

#include <memory>

#include "pbf/backend/backend.hpp"

namespace pbf {

// Needs MPI initialised (pbf::distributed::initialize) with at least as
// many planes of grid cells along the domain's longest axis as ranks.
// Throws std::runtime_error in a build without MPI.
std::unique_ptr<Backend> makeMpiBackend(const SimulationParams& params,
                                        const BackendOptions& options);

}  // namespace pbf
