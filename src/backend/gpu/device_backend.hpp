// The GPU backend (private header): Position Based Fluids written once with
// Thrust algorithms and PBF_HD kernels (device_kernels.hpp), compiled twice:
//   on_gpu  by nvcc for NVIDIA GPUs                    --device cuda
//   on_cpu  by the C++ compiler with Thrust's OpenMP   --device cuda-on-cpu
//           device system: the same source on the CPU, tested by every CTest run.
// Each build lives in its own namespace (PBF_DEVICE_NAMESPACE), so both link
// into one program. A build that is not there (no nvcc, no Thrust headers)
// is replaced by a factory that refuses, saying why (no_device.cpp).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "pbf/backend/backend.hpp"

namespace pbf::gpu {

// What a device build can do here and now.
struct DeviceStatus {
    bool built = false;         // compiled into this program
    bool usable = false;        // and a device is there to run on
    std::string description;    // the device ("NVIDIA H100 80GB HBM3, 79.1 GiB free"), or why not
    std::size_t freeBytes = 0;  // device memory free now (0 for on_cpu: host memory)
};

// Tests (tests/backend/gpu/device_stages_test.cpp): the kernels of one step
// run one at a time on start positions x and predictions x* (no predict
// stage), in the backend's particle order after its sort by cell.
struct StageOutputs {
    std::vector<std::uint32_t> input;  // the input index of each particle
    std::vector<Vec3> x, xStar;
    std::vector<float> density, lambda;  // at x*
    std::vector<Vec3> corrected;         // x* + dp into the box, out of the solids
    std::vector<Vec3> velocity;          // (x* - x) / dt
    std::vector<Vec3> xsphVelocity;      // after XSPH
    std::vector<Vec3> vorticity;         // omega (with fluid.vorticity > 0)
    // With fluid.kinematic_viscosity > 0: v + (1 s) nu lap v, the physical
    // viscosity's stage applied to v with a step of 1 s (so that a stands
    // out against v when read back).
    std::vector<Vec3> viscosityVelocity;
    // Given surface-tension settings: the surface layer's weights s at x*
    // with the density pass's rho, and v + dt a, surface tension's stage
    // with them, with those settings' constants and solver.wall_adhesion
    // (the other stages keep `params`' constants).
    std::vector<float> surfaceLayer;
    std::vector<Vec3> surfaceTensionVelocity;
    // With the same settings: the curvature force's acceleration a at x*
    // (its four kernels on v = 0 with a step of 1 s).
    std::vector<Vec3> curvatureAcceleration;
};

namespace on_gpu {
DeviceStatus status();
// The bytes a DeviceBackend of this build holds in the arrays of the two
// lists above (by their sizes, not capacities).
std::size_t particleArrayBytes(const Backend& backend);
// Throws std::runtime_error naming the device when it cannot run here.
std::unique_ptr<Backend> makeBackend(const SimulationParams& params, const BackendOptions& options);
StageOutputs runStages(const SimulationParams& params, const SolidSet* solids,
                       std::span<const Vec3> x, std::span<const Vec3> xStar, float dt,
                       const SimulationParams* surfaceTension);
}  // namespace on_gpu

namespace on_cpu {
DeviceStatus status();
std::size_t particleArrayBytes(const Backend& backend);
std::unique_ptr<Backend> makeBackend(const SimulationParams& params, const BackendOptions& options);
StageOutputs runStages(const SimulationParams& params, const SolidSet* solids,
                       std::span<const Vec3> x, std::span<const Vec3> xStar, float dt,
                       const SimulationParams* surfaceTension);
}  // namespace on_cpu

// Device memory the backend needs per particle for these settings (the
// arrays it allocates, the sort's scratch included), with the reaction
// records when a solid is coupled (rigid bodies) and the sparse grid.
// device_memory.cpp; the backend's diagnostics are tested against it.
std::size_t bytesPerParticle(const SimulationParams& params, bool coupledSolids);
// Its part in arrays of exactly one element per particle: the particle
// fields and the step arrays (device_step_arrays.hpp) these settings use.
// A running backend's figure (particleArrayBytes(const Backend&)) is tested
// against it.
std::size_t particleArrayBytes(const SimulationParams& params, bool coupledSolids);

}  // namespace pbf::gpu
