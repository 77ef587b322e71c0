// One particle in transit between MPI ranks (private header): every field of
// the particle list (pbf/core/particle_fields.hpp) and the particle's key, as one
// trivially copyable record that MPI moves as bytes. Generated from the list,
// so a field added there travels with migrations, ghosts, gathers and
// scatters without a change here.
#pragma once

#include <cstddef>
#include <cstdint>
#include <type_traits>

#include "pbf/core/particles.hpp"

namespace pbf {

struct ParticleRecord {
#define PBF_RECORD_MEMBER(name, type, components, unit, kind, description) type name[components];
    PBF_PARTICLE_FIELDS(PBF_RECORD_MEMBER)
#undef PBF_RECORD_MEMBER
    // The particle's place in the one-process memory order (key_range_halo.hpp).
    std::uint64_t key;
};
static_assert(std::is_trivially_copyable_v<ParticleRecord>);

// Particle i of `p` as a record (an optional field the store does not keep
// is zero).
ParticleRecord recordOf(const ParticleStore& p, std::size_t i, std::uint64_t key);
// Particle k of `p` (already sized) set from a record; the optional fields
// the store does not keep are left off.
void setFromRecord(ParticleStore& p, std::size_t k, const ParticleRecord& r);

inline Vec3 predictedOf(const ParticleRecord& r) {
    return {r.predicted[0], r.predicted[1], r.predicted[2]};
}

}  // namespace pbf
