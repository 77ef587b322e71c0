// The GPU backend's memory per particle (backend/gpu/device_backend.hpp):
// the arrays DeviceBackend allocates (device_backend_impl.hpp), listed here
// so that a scene can be refused before anything is allocated.
#include <cstdint>

#include "backend/cpu/grid_stencil.hpp"
#include "backend/gpu/device_backend.hpp"

namespace pbf::gpu {

std::size_t bytesPerParticle(const SimulationParams& params, bool coupledSolids) {
    constexpr std::size_t vec3 = 3 * sizeof(float);
    constexpr std::size_t scalar = sizeof(float);
    // The state: x, x*, v, rho, id.
    std::size_t bytes = 3 * vec3 + 2 * scalar;
    if (params.solver.warmStart > 0.0f) bytes += vec3;  // the last substep's acceleration
    // The step's scratch: the corrected x* (Jacobi), lambda, cell keys, the
    // sort's order, one gather buffer, and the sort's own double buffers
    // (keys and values).
    bytes += vec3 + 4 * scalar + 2 * scalar;
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

std::size_t cellTableBytes(const SimulationParams& params) {
    const grid::GridView g = grid::gridLayout(params.domain, params.kernelRadius());
    return (std::size_t{g.n[0]} * g.n[1] * g.n[2] + 1) * sizeof(std::uint32_t);
}

}  // namespace pbf::gpu
