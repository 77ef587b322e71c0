// The backend factory and the parts of the seam every backend shares.
#include "pbf/backend/backend.hpp"

#include <stdexcept>
#include <string>

#include "backend/cpu/cpu_backend.hpp"
#include "backend/mpi/mpi_backend.hpp"
#include "backend/reference/reference_backend.hpp"

namespace pbf {

std::string_view backendName(BackendKind kind) {
    switch (kind) {
        case BackendKind::Cpu:
            return "cpu";
        case BackendKind::Reference:
            return "reference";
        case BackendKind::Mpi:
            return "mpi";
    }
    return "unknown";
}

BackendKind parseBackendKind(std::string_view name) {
    for (BackendKind kind : {BackendKind::Cpu, BackendKind::Reference})
        if (name == backendName(kind)) return kind;
    throw std::invalid_argument("device: must be cpu or reference, got \"" + std::string(name) +
                                "\"");
}

std::unique_ptr<Backend> makeBackend(BackendKind kind, const SimulationParams& params,
                                     const BackendOptions& options) {
    switch (kind) {
        case BackendKind::Cpu:
            return std::make_unique<CpuBackend>(params, options);
        case BackendKind::Reference:
            return makeReferenceBackend(params);
        case BackendKind::Mpi:
            return makeMpiBackend(params, options);
    }
    throw std::invalid_argument("makeBackend: unknown backend kind");
}

StageTimes& StageTimes::operator+=(const StageTimes& o) {
#define PBF_ADD_TIME(member, description) member += o.member;
    PBF_STAGE_TIMES(PBF_ADD_TIME)
#undef PBF_ADD_TIME
    return *this;
}

StageTimes StageTimes::operator*(double factor) const {
    StageTimes r;
#define PBF_SCALE_TIME(member, description) r.member = member * factor;
    PBF_STAGE_TIMES(PBF_SCALE_TIME)
#undef PBF_SCALE_TIME
    return r;
}

}  // namespace pbf
