// The GPU backend's source compiled for the CPU: Thrust's OpenMP device
// system runs every kernel as an OpenMP loop (--device cuda-on-cpu). The
// same code as build_on_gpu.cu, tested by every CTest run. CMake compiles
// this file with -DTHRUST_DEVICE_SYSTEM=THRUST_DEVICE_SYSTEM_OMP.
#include <omp.h>

#define PBF_DEVICE_KIND BackendKind::CudaOnCpu
#define PBF_DEVICE_NAMESPACE on_cpu
#define PBF_DEVICE_OPENMP 1
#include "backend/gpu/device_backend_impl.hpp"

namespace pbf::gpu::on_cpu {

DeviceStatus status() {
    DeviceStatus s;
    s.built = true;
    s.usable = true;
    s.freeBytes = 0;  // host memory: the World asks the machine
    s.description = "the GPU backend's source on the CPU (Thrust " +
                    std::to_string(THRUST_MAJOR_VERSION) + "." +
                    std::to_string(THRUST_MINOR_VERSION) + ", OpenMP, " +
                    std::to_string(threadCount()) + " threads)";
    return s;
}

std::unique_ptr<Backend> makeBackend(const SimulationParams& params, const BackendOptions&) {
    return std::make_unique<DeviceBackend>(PBF_DEVICE_KIND, params);
}

}  // namespace pbf::gpu::on_cpu
