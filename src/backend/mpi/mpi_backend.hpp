// The distributed backend (private header): the CPU solver on one range of
// cell keys per MPI rank (backend/mpi/key_range_halo.hpp does the
// decomposition, migration and halos; backend/cpu/solver.hpp the work).
#pragma once

#include <memory>

#include "pbf/backend/backend.hpp"

namespace pbf {

// Needs MPI initialised (pbf::distributed::initialize); any number of ranks
// (a rank whose key range holds no particle just waits at the exchanges).
// Throws std::runtime_error in a build without MPI.
std::unique_ptr<Backend> makeMpiBackend(const SimulationParams& params,
                                        const BackendOptions& options);

}  // namespace pbf
