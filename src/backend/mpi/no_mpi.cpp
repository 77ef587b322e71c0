// makeMpiBackend in a build without MPI (PBF_MPI off).
#include <stdexcept>

#include "backend/mpi/mpi_backend.hpp"

namespace pbf {

std::unique_ptr<Backend> makeMpiBackend(const SimulationParams&, const BackendOptions&) {
    throw std::runtime_error(
        "the mpi backend needs a build with MPI (install libopenmpi-dev, cmake -DPBF_MPI=ON)");
}

}  // namespace pbf
