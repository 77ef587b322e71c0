// The particle arrays of a checkpoint (private header): every field of the
// particle list (pbf/core/particle_fields.hpp) but the solver's working copies,
// in list order, each component an array with its length.
#pragma once

#include <cstddef>
#include <vector>

#include "io/binary_stream.hpp"
#include "pbf/core/particles.hpp"

namespace pbf::detail {

void writeParticleArrays(BinaryWriter& w, const ParticleStore& p);
// Reads what writeParticleArrays wrote into `p` (its working fields are left
// empty); throws IoError when the arrays' lengths disagree.
void readParticleArrays(BinaryReader& r, ParticleStore& p);
// Bytes per particle of the arrays, optional fields counted as on.
std::size_t savedBytesPerParticle();

// The arrays writeParticleArrays writes, in its order: each component's
// values (null when it holds none), bytes per value, and whether the
// store keeps it (an optional field that is off is written empty).
struct SavedArray {
    const void* data;
    std::size_t valueBytes;
    bool kept;
};
std::vector<SavedArray> savedArrays(const ParticleStore& p);

}  // namespace pbf::detail
