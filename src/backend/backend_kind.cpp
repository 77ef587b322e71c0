// The backends' names and the limits every backend shares.
#include <stdexcept>
#include <string>

#include "pbf/backend/backend.hpp"

namespace pbf {

std::string_view backendName(BackendKind kind) {
    switch (kind) {
        case BackendKind::Cpu:
            return "cpu";
        case BackendKind::Reference:
            return "reference";
        case BackendKind::Mpi:
            return "mpi";
        case BackendKind::Cuda:
            return "cuda";
        case BackendKind::CudaOnCpu:
            return "cuda-on-cpu";
    }
    return "unknown";
}

void checkParticlesPerProcess(BackendKind kind, std::size_t held, std::size_t added) {
    if (added <= kMaxParticlesPerProcess && held <= kMaxParticlesPerProcess - added) return;
    throw std::length_error(
        "the " + std::string(backendName(kind)) + " backend holds at most " +
        std::to_string(kMaxParticlesPerProcess) + " particles in one process (it indexes them " +
        "with 32 bits); " + std::to_string(added) + " more on top of " + std::to_string(held) +
        " would exceed that: use larger particles, or split the run over MPI ranks (`mpirun -n "
        "N pbf run ...`)");
}

std::vector<BackendKind> deviceKinds() {
    return {BackendKind::Cpu, BackendKind::Reference, BackendKind::Cuda, BackendKind::CudaOnCpu};
}

BackendKind parseBackendKind(std::string_view name) {
    for (BackendKind kind : deviceKinds())
        if (name == backendName(kind)) return kind;
    throw std::invalid_argument("device: must be cpu, reference, cuda or cuda-on-cpu, got \"" +
                                std::string(name) + "\"");
}

}  // namespace pbf
