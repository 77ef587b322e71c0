// The device the GPU backend's tests run on: cuda-on-cpu (the backend's
// source on the CPU) by default; PBF_TEST_DEVICE=cuda runs the same cases
// on an NVIDIA GPU (scripts/gpu_check.sh). A device that cannot run here
// (a build without it, no GPU) skips the tests with the reason.
#pragma once

#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

#include "backend/gpu/device_backend.hpp"
#include "pbf/backend/backend.hpp"

namespace pbf::test {

inline BackendKind deviceUnderTest() {
    const char* name = std::getenv("PBF_TEST_DEVICE");
    return name && *name ? parseBackendKind(name) : BackendKind::CudaOnCpu;
}

inline gpu::StageOutputs runDeviceStages(const SimulationParams& params, const SolidSet* solids,
                                         std::span<const Vec3> x, std::span<const Vec3> xStar,
                                         float dt,
                                         const SimulationParams* surfaceTension = nullptr) {
    return deviceUnderTest() == BackendKind::Cuda
               ? gpu::on_gpu::runStages(params, solids, x, xStar, dt, surfaceTension)
               : gpu::on_cpu::runStages(params, solids, x, xStar, dt, surfaceTension);
}

}  // namespace pbf::test

// Skips the test when the device under test cannot run here, saying why.
#define PBF_REQUIRE_DEVICE()                                                                 \
    do {                                                                                     \
        const ::pbf::DeviceInfo device_ = ::pbf::deviceInfo(::pbf::test::deviceUnderTest()); \
        if (!device_.usable)                                                                 \
            GTEST_SKIP() << "device " << ::pbf::backendName(device_.kind) << ": "            \
                         << device_.description;                                             \
    } while (false)
