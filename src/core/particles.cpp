#include "pbf/core/particles.hpp"

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <numeric>
#include <type_traits>
#include <utility>

#include "core/parallel.hpp"

namespace pbf {
namespace {

constexpr ParticleFieldInfo kFields[] = {
#define PBF_FIELD_INFO(name, type, components, unit, kind, description) \
    {#name, unit, components, ParticleFieldKind::kind, description},
    PBF_PARTICLE_FIELDS(PBF_FIELD_INFO)
#undef PBF_FIELD_INFO
};

template <class T>
void permute(std::vector<T>& values, std::span<const std::uint32_t> perm, std::vector<T>& scratch) {
    scratch.resize(values.size());
    detail::parallelFor(values.size(), [&](std::size_t begin, std::size_t end) {
        for (std::size_t k = begin; k < end; ++k) scratch[k] = values[perm[k]];
    });
    values.swap(scratch);
}

// The same through lent memory: gathered into it, copied back (one more
// pass over the field, instead of a scratch array of its width per particle).
template <class T>
void permute(std::vector<T>& values, std::span<const std::uint32_t> perm, T* scratch) {
    detail::parallelFor(values.size(), [&](std::size_t begin, std::size_t end) {
        for (std::size_t k = begin; k < end; ++k) scratch[k] = values[perm[k]];
    });
    detail::parallelFor(values.size(), [&](std::size_t begin, std::size_t end) {
        std::copy(scratch + begin, scratch + end, values.begin() + std::ptrdiff_t(begin));
    });
}

static_assert(std::size(kFields) <= 32, "keptOptionalFields is a 32-bit mask");

}  // namespace

// Whether a field holds values for the particles: always, except an
// optional field while it is off.
bool ParticleStore::holdsValues(const ParticleFieldInfo& field) const {
    const auto index = static_cast<std::uint32_t>(&field - kFields);
    return field.kind != ParticleFieldKind::Optional || ((optionalOn_ >> index) & 1u) != 0;
}

std::span<const ParticleFieldInfo> ParticleStore::fields() {
    return kFields;
}

void ParticleStore::reserve(std::size_t n) {
    forEachField([&](const ParticleFieldInfo& field, auto& a) {
        if (holdsValues(field))
            for (auto* c : componentsOf(a)) c->reserve(n);
    });
}

void ParticleStore::resize(std::size_t n) {
    // An optional field is decided on by whether it holds values now: a
    // store without particles keeps its optional fields off.
    forEachField([&](const ParticleFieldInfo& field, auto& a) {
        if (holdsValues(field))
            for (auto* c : componentsOf(a)) c->resize(n);
    });
}

void ParticleStore::keepOptionalFields(std::uint32_t mask) {
    const std::size_t n = size();
    std::uint32_t onMask = 0;
    forEachField([&](const ParticleFieldInfo& field, auto& a) {
        const auto bit = std::uint32_t{1} << static_cast<std::uint32_t>(&field - kFields);
        if (field.kind != ParticleFieldKind::Optional) return;
        const bool on = (mask & bit) != 0;
        if (on) onMask |= bit;
        for (auto* c : componentsOf(a)) {
            if (!on)
                c->clear();
            else if (c->size() != n)
                c->assign(n, {});
        }
    });
    optionalOn_ = onMask;
}

void ParticleStore::keepOptionalField(ParticleField field, bool on) {
    const std::uint32_t bit = std::uint32_t{1} << static_cast<std::uint32_t>(field);
    if (on == kept(field)) return;
    keepOptionalFields(on ? optionalOn_ | bit : optionalOn_ & ~bit);
}

void ParticleStore::add(const Vec3& x, const Vec3& v, float restDensity) {
    const std::size_t i = size();
    resize(i + 1);
    position.set(i, x);
    predicted.set(i, x);
    velocity.set(i, v);
    density[i] = restDensity;
    id[i] = nextId_++;
}

void ParticleStore::copyParticle(std::size_t to, const ParticleStore& from, std::size_t i) {
    // Both stores have the same fields: walk them in step.
#define PBF_COPY_FIELD(name, type, components, unit, kind, description)              \
    {                                                                                \
        const auto source = componentsOf(from.name);                                 \
        const auto target = componentsOf(name);                                      \
        for (std::size_t c = 0; c < target.size(); ++c)                              \
            if (!target[c]->empty())                                                 \
                (*target[c])[to] = i < source[c]->size() ? (*source[c])[i] : type{}; \
    }
    PBF_PARTICLE_FIELDS(PBF_COPY_FIELD)
#undef PBF_COPY_FIELD
}

void ParticleStore::reorder(std::span<const std::uint32_t> perm, std::span<std::byte> scratch) {
    forEachField([&](const ParticleFieldInfo&, auto& a) {
        for (auto* c : componentsOf(a)) {
            if (c->size() != perm.size()) continue;  // an optional field that is off
            using T = typename std::remove_reference_t<decltype(*c)>::value_type;
            if constexpr (std::is_same_v<T, float>) {
                permute(*c, perm, scratchFloat_);
            } else {
                static_assert(alignof(T) <= alignof(std::uint64_t));
                const bool lent =
                    scratch.size() >= sizeof(T) * perm.size() &&
                    reinterpret_cast<std::uintptr_t>(scratch.data()) % alignof(T) == 0;
                if (!lent) scratchWide_.resize((sizeof(T) * perm.size() + 7) / 8);
                permute(*c, perm,
                        lent ? reinterpret_cast<T*>(scratch.data())
                             : reinterpret_cast<T*>(scratchWide_.data()));
            }
        }
    });
}

void ParticleStore::keepRange(std::size_t begin, std::size_t end) {
    forEachField([&](const ParticleFieldInfo&, auto& a) {
        for (auto* values : componentsOf(a)) {
            if (values->empty()) continue;  // an optional field that is off
            values->erase(values->begin() + static_cast<std::ptrdiff_t>(end), values->end());
            values->erase(values->begin(), values->begin() + static_cast<std::ptrdiff_t>(begin));
        }
    });
}

void ParticleStore::keepOnly(std::span<const std::uint32_t> kept) {
    const std::size_t n = size();
    forEachField([&](const ParticleFieldInfo&, auto& a) {
        for (auto* values : componentsOf(a)) {
            if (values->size() != n) continue;  // an optional field that is off
            // In place: kept[j] >= j, so no value is overwritten before it is read.
            for (std::size_t j = 0; j < kept.size(); ++j) (*values)[j] = (*values)[kept[j]];
            values->resize(kept.size());
        }
    });
}

std::vector<std::uint32_t> ParticleStore::orderById() const {
    std::vector<std::uint32_t> order(size());
    std::iota(order.begin(), order.end(), 0u);
    std::sort(order.begin(), order.end(),
              [&](std::uint32_t a, std::uint32_t b) { return id[a] < id[b]; });
    return order;
}

std::size_t ParticleStore::memoryBytes() const {
    std::size_t bytes =
        sizeof(float) * scratchFloat_.capacity() + sizeof(std::uint64_t) * scratchWide_.capacity();
    forEachField([&](const ParticleFieldInfo&, const auto& a) {
        for (const auto* c : componentsOf(a))
            bytes +=
                sizeof(typename std::remove_pointer_t<decltype(c)>::value_type) * c->capacity();
    });
    return bytes;
}

}  // namespace pbf
