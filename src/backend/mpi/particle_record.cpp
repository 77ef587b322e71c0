#include "backend/mpi/particle_record.hpp"

namespace pbf {
namespace {

template <class Array, class T, std::size_t N>
void pack(const Array& array, std::size_t i, T (&out)[N]) {
    const auto components = componentsOf(array);
    for (std::size_t c = 0; c < N; ++c)
        out[c] = i < components[c]->size() ? (*components[c])[i] : T{};
}

template <class Array, class T, std::size_t N>
void unpack(const T (&in)[N], std::size_t k, Array& array) {
    const auto components = componentsOf(array);
    for (std::size_t c = 0; c < N; ++c)
        if (k < components[c]->size()) (*components[c])[k] = in[c];
}

}  // namespace

ParticleRecord recordOf(const ParticleStore& p, std::size_t i, std::uint64_t key) {
    ParticleRecord r;
#define PBF_PACK_FIELD(name, type, components, unit, kind, description) pack(p.name, i, r.name);
    PBF_PARTICLE_FIELDS(PBF_PACK_FIELD)
#undef PBF_PACK_FIELD
    r.key = key;
    return r;
}

void setFromRecord(ParticleStore& p, std::size_t k, const ParticleRecord& r) {
#define PBF_UNPACK_FIELD(name, type, components, unit, kind, description) unpack(r.name, k, p.name);
    PBF_PARTICLE_FIELDS(PBF_UNPACK_FIELD)
#undef PBF_UNPACK_FIELD
}

}  // namespace pbf
