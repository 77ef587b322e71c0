// The backend factory and the parts of the seam every backend shares.
#include "pbf/backend/backend.hpp"

#include <stdexcept>
#include <string>

#include "backend/cpu/cpu_backend.hpp"
#include "backend/gpu/device_backend.hpp"
#include "backend/mpi/mpi_backend.hpp"
#include "backend/reference/reference_backend.hpp"

namespace pbf {

DeviceInfo deviceInfo(BackendKind kind) {
    DeviceInfo info;
    info.kind = kind;
    gpu::DeviceStatus s;
    switch (kind) {
        case BackendKind::Cuda:
            s = gpu::on_gpu::status();
            break;
        case BackendKind::CudaOnCpu:
            s = gpu::on_cpu::status();
            break;
        case BackendKind::Mpi:
#if defined(PBF_HAVE_MPI)
            s = {true, true,
                 "the cpu solver on one range of the cell key per MPI rank (mpirun -np N)", 0};
#else
            s = {false, false, "this pbf was built without MPI", 0};
#endif
            break;
        case BackendKind::Cpu:
            s = {true, true, "SIMD (Highway), OpenMP", 0};
            break;
        case BackendKind::Reference:
            s = {true, true, "scalar, one function per equation (the test oracle)", 0};
            break;
    }
    info.built = s.built;
    info.usable = s.usable;
    info.description = s.description;
    info.freeBytes = s.freeBytes;
    return info;
}

std::size_t deviceBytesPerParticle(const SimulationParams& params, bool rigidBodies) {
    return gpu::bytesPerParticle(params, rigidBodies);
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
        case BackendKind::Cuda:
            return gpu::on_gpu::makeBackend(params, options);
        case BackendKind::CudaOnCpu:
            return gpu::on_cpu::makeBackend(params, options);
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
