// The GPU backend's CPU build compiled for pbf_particle_fields_tests (with
// the two extra fields of extra_particle_fields.hpp): its device arrays come
// from the same list (backend/gpu/device_backend_impl.hpp, DeviceParticles).
#include <omp.h>

#define PBF_DEVICE_KIND BackendKind::CudaOnCpu
#define PBF_DEVICE_NAMESPACE on_cpu_fields_test
#define PBF_DEVICE_OPENMP 1
#include "backend/gpu/device_backend_impl.hpp"

namespace pbf::gpu::on_cpu_fields_test {

std::unique_ptr<Backend> makeBackend(const SimulationParams& params) {
    return std::make_unique<DeviceBackend>(PBF_DEVICE_KIND, params);
}

}  // namespace pbf::gpu::on_cpu_fields_test
