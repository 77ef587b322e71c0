// The GPU backend's CPU build once more, against Debian's Thrust 1.17
// (libthrust-dev, libcub-dev) where the main build uses the CUDA toolkit's
// CCCL: the source sticks to the API both share, and this copy (Thrust in
// its own namespace, THRUST_CUB_WRAPPED_NAMESPACE) lets a test check that
// both give the same bits (device_thrust_versions_test.cpp). Compiled with
// -DTHRUST_DEVICE_SYSTEM=THRUST_DEVICE_SYSTEM_OMP and Debian's headers.
#include <omp.h>

#define PBF_DEVICE_KIND BackendKind::CudaOnCpu
#define PBF_DEVICE_NAMESPACE on_cpu_thrust117
#define PBF_DEVICE_OPENMP 1
#include "backend/gpu/device_backend_impl.hpp"

namespace pbf::gpu::on_cpu_thrust117 {

std::unique_ptr<Backend> makeBackend(const SimulationParams& params) {
    return std::make_unique<DeviceBackend>(PBF_DEVICE_KIND, params);
}

int thrustVersion() {
    return THRUST_VERSION;
}

}  // namespace pbf::gpu::on_cpu_thrust117
