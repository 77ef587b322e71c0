// The GPU backend compiled by nvcc for NVIDIA GPUs (--device cuda): the
// same source as build_on_cpu.cpp, whose CPU build the tests run.
#include <cuda_runtime.h>

#define PBF_DEVICE_KIND BackendKind::Cuda
#define PBF_DEVICE_NAMESPACE on_gpu
#include "backend/gpu/device_backend_impl.hpp"

namespace pbf::gpu::on_gpu {
namespace {

std::string gibibytes(std::size_t bytes) {
    const double g = double(bytes) / double(1ull << 30);
    const long tenths = static_cast<long>(g * 10.0 + 0.5);
    return std::to_string(tenths / 10) + "." + std::to_string(tenths % 10) + " GiB";
}

}  // namespace

DeviceStatus status() {
    DeviceStatus s;
    s.built = true;
    int count = 0;
    const cudaError_t error = cudaGetDeviceCount(&count);
    if (error != cudaSuccess || count == 0) {
        s.description = std::string("no NVIDIA GPU found (") +
                        (error != cudaSuccess ? cudaGetErrorString(error) : "no CUDA device") + ")";
        cudaGetLastError();  // clear the sticky error
        return s;
    }
    int device = 0;
    cudaGetDevice(&device);
    cudaDeviceProp properties{};
    cudaGetDeviceProperties(&properties, device);
    const int capability = 10 * properties.major + properties.minor;
    if (capability < PBF_CUDA_MIN_ARCH) {
        s.description = std::string(properties.name) + " (sm_" + std::to_string(capability) +
                        ") is older than sm_" + std::to_string(PBF_CUDA_MIN_ARCH) +
                        ", the oldest GPU this pbf was built for (CMAKE_CUDA_ARCHITECTURES)";
        return s;
    }
    std::size_t freeBytes = 0, totalBytes = 0;
    if (cudaMemGetInfo(&freeBytes, &totalBytes) != cudaSuccess) {
        s.description = std::string(properties.name) + ": cannot query its memory";
        cudaGetLastError();
        return s;
    }
    s.usable = true;
    s.freeBytes = freeBytes;
    s.description = std::string(properties.name) + " (sm_" + std::to_string(capability) + "), " +
                    gibibytes(freeBytes) + " of " + gibibytes(totalBytes) + " free";
    return s;
}

std::unique_ptr<Backend> makeBackend(const SimulationParams& params, const BackendOptions&) {
    const DeviceStatus s = status();
    if (!s.usable) throw std::runtime_error("device cuda: " + s.description);
    return std::make_unique<DeviceBackend>(PBF_DEVICE_KIND, params);
}

}  // namespace pbf::gpu::on_gpu
