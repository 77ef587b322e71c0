// The GPU backend's builds that this program lacks (backend/gpu/device_backend.hpp):
// the factory says why and how to get it. Compiled with PBF_NO_CUDA_BUILD
// and/or PBF_NO_THRUST_BUILD.
#include <stdexcept>

#include "backend/gpu/device_backend.hpp"

namespace pbf::gpu {
namespace {

[[noreturn, maybe_unused]] void unavailable(const DeviceStatus& s, const char* device) {
    throw std::runtime_error(std::string("device ") + device + ": " + s.description);
}

}  // namespace

#if defined(PBF_NO_CUDA_BUILD)
DeviceStatus on_gpu::status() {
    DeviceStatus s;
    s.description =
        "this pbf was built without CUDA (nvcc was not found when it was configured, or "
        "-DPBF_CUDA=OFF); install the CUDA toolkit and configure again";
    return s;
}
std::unique_ptr<Backend> on_gpu::makeBackend(const SimulationParams&, const BackendOptions&) {
    unavailable(status(), "cuda");
}
StageOutputs on_gpu::runStages(const SimulationParams&, const SolidSet*, std::span<const Vec3>,
                               std::span<const Vec3>, float, const SimulationParams*) {
    unavailable(status(), "cuda");
}
std::size_t on_gpu::particleArrayBytes(const Backend&) {
    unavailable(status(), "cuda");
}
#endif

#if defined(PBF_NO_THRUST_BUILD)
DeviceStatus on_cpu::status() {
    DeviceStatus s;
    s.description =
        "this pbf was built without Thrust (neither the CUDA toolkit's CCCL nor Debian's "
        "libthrust-dev and libcub-dev were found when it was configured)";
    return s;
}
std::unique_ptr<Backend> on_cpu::makeBackend(const SimulationParams&, const BackendOptions&) {
    unavailable(status(), "cuda-on-cpu");
}
StageOutputs on_cpu::runStages(const SimulationParams&, const SolidSet*, std::span<const Vec3>,
                               std::span<const Vec3>, float, const SimulationParams*) {
    unavailable(status(), "cuda-on-cpu");
}
std::size_t on_cpu::particleArrayBytes(const Backend&) {
    unavailable(status(), "cuda-on-cpu");
}
#endif

}  // namespace pbf::gpu
