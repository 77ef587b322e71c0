// The GPU backend's memory per particle (backend/gpu/device_backend.hpp),
// so that a scene can be refused before anything is allocated. The arrays
// sized per particle come from the lists DeviceBackend is built from: the
// particle fields (include/pbf/core/particle_fields.hpp) and the step arrays
// (device_step_arrays.hpp); the search's and the sparse grid's arrays are
// sized here by hand.
#include <cstdint>

#include "backend/gpu/device_backend.hpp"
#include "backend/gpu/device_step_arrays.hpp"
#include "pbf/core/particle_fields.hpp"

namespace pbf::gpu {

std::size_t particleArrayBytes(const SimulationParams& params, bool coupledSolids) {
    const StepTerms terms = stepTerms(params, SolverConstants::from(params), false);
    std::size_t bytes = 0;
    // The particle fields; an optional one only while its feature is on.
    const auto fieldInUse = [&](ParticleField field, ParticleFieldKind kind) {
        if (kind != ParticleFieldKind::Optional) return true;
        if (field == ParticleField::solveAcceleration) return terms.warmStart;
        return true;  // a field added to the list: counted
    };
#define PBF_FIELD_BYTES(name, type, components, unit, kind, description) \
    if (fieldInUse(ParticleField::name, ParticleFieldKind::kind))        \
        bytes += std::size_t{components} * sizeof(type);
    PBF_PARTICLE_FIELDS(PBF_FIELD_BYTES)
#undef PBF_FIELD_BYTES
    // The step arrays the settings need.
#define PBF_STEP_ARRAY_BYTES(name, type, components, use)        \
    if (stepArrayInUse(StepArrayUse::use, terms, coupledSolids)) \
        bytes += std::size_t{components} * sizeof(type);
    PBF_DEVICE_STEP_ARRAYS(PBF_STEP_ARRAY_BYTES)
#undef PBF_STEP_ARRAY_BYTES
    return bytes;
}

std::size_t bytesPerParticle(const SimulationParams& params, bool coupledSolids) {
    std::size_t bytes = particleArrayBytes(params, coupledSolids);
    // The search: the 64-bit cell keys and the sort's order, the radix
    // sort's second buffers of both (the second key buffer also gathers the
    // 64-bit ids), each particle's cell, and the reorder's gather buffer of
    // the float fields.
    bytes +=
        2 * (sizeof(std::uint64_t) + sizeof(std::uint32_t)) + sizeof(std::uint32_t) + sizeof(float);
    // The sparse grid (backend/sparse_grid.hpp), planned at a cell per four
    // particles (water at rest has eight per cell; spray fewer) and a row of
    // the key (up to 64 cells along x) per sixteen: per cell its key, start,
    // row key and row; per row its key, mask, first cell and 27 neighbouring
    // rows.
    bytes += (2 * sizeof(std::uint64_t) + 2 * sizeof(std::uint32_t)) / 4;
    bytes += (2 * sizeof(std::uint64_t) + sizeof(std::uint32_t) + 27 * sizeof(std::int32_t)) / 16;
    // The neighbour lists (device_kernels.hpp, ListNeighbors): an offset and
    // 4 bytes per neighbour, planned at 40 neighbours (water at rest has
    // 26-33 within h = 2 spacings; the dam break averages 28.5, the list
    // keeps an eighth spare).
    bytes += sizeof(std::uint64_t) + 40 * sizeof(std::uint32_t);
    return bytes;
}

}  // namespace pbf::gpu
