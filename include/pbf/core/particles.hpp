// Structure-of-arrays particle storage.
//
// Every per-particle attribute is its own contiguous array; a 3-vector
// attribute is three float arrays (x, y, z) so that passes over one component
// stream through memory. The attributes are the fields listed once in
// pbf/core/particle_fields.hpp. `ParticleStore::reorder` is the one place that
// permutes particles: the solver sorts them by grid cell every step so that
// neighbours sit next to each other in memory, and `id` keeps each
// particle's stable identity for output files.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <type_traits>
#include <vector>

#include "pbf/core/particle_fields.hpp"
#include "pbf/core/vec3.hpp"

namespace pbf {

// Three float arrays holding one 3-vector attribute.
struct Float3Array {
    std::vector<float> x;
    std::vector<float> y;
    std::vector<float> z;

    std::size_t size() const { return x.size(); }
    void resize(std::size_t n) {
        x.resize(n);
        y.resize(n);
        z.resize(n);
    }
    void reserve(std::size_t n) {
        x.reserve(n);
        y.reserve(n);
        z.reserve(n);
    }
    Vec3 get(std::size_t i) const { return {x[i], y[i], z[i]}; }
    void set(std::size_t i, const Vec3& v) {
        x[i] = v.x;
        y[i] = v.y;
        z[i] = v.z;
    }
    void push_back(const Vec3& v) {
        x.push_back(v.x);
        y.push_back(v.y);
        z.push_back(v.z);
    }
};

// The storage of a field of the list: three float arrays for a 3-vector,
// one array otherwise.
template <class T, int Components>
using ParticleFieldArray = std::conditional_t<Components == 3, Float3Array, std::vector<T>>;

// The component arrays of a field's storage, for code that treats every
// field alike (reorder, checkpoints).
inline std::array<std::vector<float>*, 3> componentsOf(Float3Array& a) {
    return {&a.x, &a.y, &a.z};
}
inline std::array<const std::vector<float>*, 3> componentsOf(const Float3Array& a) {
    return {&a.x, &a.y, &a.z};
}
template <class T>
std::array<std::vector<T>*, 1> componentsOf(std::vector<T>& a) {
    return {&a};
}
template <class T>
std::array<const std::vector<T>*, 1> componentsOf(const std::vector<T>& a) {
    return {&a};
}

class ParticleStore {
  public:
    // The fields of include/pbf/core/particle_fields.hpp, one member each:
    //   Float3Array position;          x, metres
    //   Float3Array predicted;         x*, metres (solver working positions)
    //   Float3Array velocity;          v, metres per second
    //   std::vector<float> density;    last density estimate, kg/m^3
    //   std::vector<std::uint64_t> id; stable identity, 0-based
    //   Float3Array solveAcceleration; warm start (empty while it is off)
#define PBF_STORE_MEMBER(name, type, components, unit, kind, description) \
    ParticleFieldArray<type, components> name;
    PBF_PARTICLE_FIELDS(PBF_STORE_MEMBER)
#undef PBF_STORE_MEMBER

    // The list as data, in list order.
    static std::span<const ParticleFieldInfo> fields();

    // Calls fn(info, storage) for every field, in list order.
    template <class Fn>
    void forEachField(Fn&& fn) {
        std::size_t k = 0;
#define PBF_VISIT_FIELD(name, type, components, unit, kind, description) fn(fields()[k++], name);
        PBF_PARTICLE_FIELDS(PBF_VISIT_FIELD)
#undef PBF_VISIT_FIELD
    }
    template <class Fn>
    void forEachField(Fn&& fn) const {
        std::size_t k = 0;
#define PBF_VISIT_FIELD(name, type, components, unit, kind, description) fn(fields()[k++], name);
        PBF_PARTICLE_FIELDS(PBF_VISIT_FIELD)
#undef PBF_VISIT_FIELD
    }

    std::size_t size() const {
        return id.size();
    }
    void reserve(std::size_t n);
    // Appends a particle with the next free id; density starts at `restDensity`.
    void add(const Vec3& x, const Vec3& v, float restDensity);
    // Resizes every field to n particles (an optional field only while it is
    // on); new particles are zero, ids included: the caller sets them.
    void resize(std::size_t n);
    // The optional fields that are on (bit k: the k-th field of the list),
    // and switching them on (zeros for every particle) or off (emptied).
    // An optional field holds one value per particle while it is on, none
    // while it is off; the store remembers which even while it is empty.
    std::uint32_t keptOptionalFields() const {
        return optionalOn_;
    }
    void keepOptionalFields(std::uint32_t mask);
    bool kept(ParticleField field) const {
        return (optionalOn_ >> int(field)) & 1u;
    }
    void keepOptionalField(ParticleField field, bool on);
    // Sets particle `to` to particle `i` of `from`, every field (an optional
    // field that `from` does not keep becomes zero).
    void copyParticle(std::size_t to, const ParticleStore& from, std::size_t i);
    // Permutes every array: new index k takes the particle at old index perm[k].
    // `perm` must be a permutation of [0, size()). `scratch`: memory the
    // caller lends for the 64-bit fields (the ids) while it is idle, at
    // least 8 bytes per particle; without it the store keeps its own.
    void reorder(std::span<const std::uint32_t> perm, std::span<std::byte> scratch = {});
    // Keeps the particles [begin, end) (in order) and drops the others.
    void keepRange(std::size_t begin, std::size_t end);
    // Keeps the particles at the indices `kept` (ascending), in that order,
    // and drops the others (particles leaving through an outlet).
    void keepOnly(std::span<const std::uint32_t> kept);
    // Bytes held by the particle arrays and the reorder scratch.
    std::size_t memoryBytes() const;
    // Indices of the particles sorted by id (for writing files in a stable order).
    std::vector<std::uint32_t> orderById() const;
    // The id the next add() gives (saved and restored by checkpoints).
    std::uint64_t nextId() const {
        return nextId_;
    }
    void setNextId(std::uint64_t next) {
        nextId_ = next;
    }

  private:
    bool holdsValues(const ParticleFieldInfo& field) const;

    std::uint64_t nextId_ = 0;
    std::uint32_t optionalOn_ = 0;
    std::vector<float> scratchFloat_;
    std::vector<std::uint64_t> scratchWide_;  // the ids' scratch where reorder is lent none
};

}  // namespace pbf
