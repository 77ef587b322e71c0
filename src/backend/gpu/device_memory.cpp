// The GPU backend's memory per particle (backend/gpu/device_backend.hpp):
// the arrays DeviceBackend allocates (device_backend_impl.hpp), listed here
// so that a scene can be refused before anything is allocated.
#include <cstdint>

#include "backend/gpu/device_backend.hpp"

namespace pbf::gpu {

std::size_t bytesPerParticle(const SimulationParams& params, bool coupledSolids) {
    constexpr std::size_t vec3 = 3 * sizeof(float);
    constexpr std::size_t scalar = sizeof(float);
    // The state: x, x*, v, rho, id.
    std::size_t bytes = 3 * vec3 + 2 * scalar;
    if (params.solver.warmStart > 0.0f) bytes += vec3;  // the last substep's acceleration
    // The step's scratch: the corrected x* (Jacobi), lambda, one gather
    // buffer; the sort's 64-bit cell keys and order, its second buffers of
    // both, and each particle's cell.
    bytes += vec3 + 2 * scalar;
    bytes += 2 * (sizeof(std::uint64_t) + sizeof(std::uint32_t)) + sizeof(std::uint32_t);
    // The sparse grid (backend/sparse_grid.hpp), planned at a cell per two
    // particles (water at rest has about eight per cell; spray fewer) and
    // a 4x4x4 block per eight: per cell its key, start, block key and block;
    // per block its key, mask, first cell and 27 neighbouring blocks.
    bytes += (2 * sizeof(std::uint64_t) + 2 * sizeof(std::uint32_t)) / 2;
    bytes += (2 * sizeof(std::uint64_t) + sizeof(std::uint32_t) + 27 * sizeof(std::int32_t)) / 8;
    // The neighbour lists (device_kernels.hpp, ListNeighbors): an offset and
    // 4 bytes per neighbour, planned at 40 neighbours (water at rest has
    // 26-33 within h = 2 spacings; the dam break averages 28.5, the list
    // keeps an eighth spare).
    bytes += sizeof(std::uint64_t) + 40 * sizeof(std::uint32_t);
    // v after XSPH, or before it for the physical viscosity's Jacobi read.
    if (params.fluid.viscosity > 0.0f || params.fluid.vorticity > 0.0f ||
        params.fluid.kinematicViscosity > 0.0f)
        bytes += vec3;
    if (params.fluid.vorticity > 0.0f) bytes += vec3;  // omega
    // The continuum surface stress T_i: six floats.
    if (params.fluid.surfaceTension > 0.0f) bytes += 6 * scalar;
    // Two slots of reaction records (solid, x, d) for coupled solids.
    if (coupledSolids) bytes += 2 * (scalar + 2 * vec3);
    return bytes;
}

}  // namespace pbf::gpu
