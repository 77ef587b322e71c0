#include "backend/reference/reference_backend.hpp"

#include <stdexcept>

namespace pbf {

// Placeholder until the scalar reference backend lands (same series of commits).
std::unique_ptr<Backend> makeReferenceBackend(const SimulationParams&) {
    throw std::invalid_argument("device: the reference backend is not built yet");
}

}  // namespace pbf
