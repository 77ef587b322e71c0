#include "io/checkpoint_particles.hpp"

#include <string>
#include <type_traits>

namespace pbf::detail {
namespace {

template <class Component>
using ValueType = typename std::remove_cvref_t<std::remove_pointer_t<Component>>::value_type;

}  // namespace

void writeParticleArrays(BinaryWriter& w, const ParticleStore& p) {
    // An optional field that is off is written empty.
    p.forEachField([&](const ParticleFieldInfo& field, const auto& a) {
        if (field.kind == ParticleFieldKind::Working) return;
        for (const auto* component : componentsOf(a)) w.array(*component);
    });
}

void readParticleArrays(BinaryReader& r, ParticleStore& p) {
    constexpr const char* kAxes[] = {".x", ".y", ".z"};
    p.forEachField([&](const ParticleFieldInfo& field, auto& a) {
        if (field.kind == ParticleFieldKind::Working) return;
        const auto components = componentsOf(a);
        for (std::size_t k = 0; k < components.size(); ++k) {
            const std::string what =
                field.name + std::string(components.size() == 3 ? kAxes[k] : "");
            r.array(*components[k], what.c_str());
        }
    });
    // The checksum passed, so this only fails for a file written by a buggy
    // or foreign program; still, never hand an inconsistent store to the solver.
    const std::size_t n = p.id.size();
    bool consistent = true;
    std::uint32_t optionalOn = 0, bit = 1;
    p.forEachField([&](const ParticleFieldInfo& field, const auto& a) {
        if (field.kind == ParticleFieldKind::Optional && !componentsOf(a)[0]->empty())
            optionalOn |= bit;
        bit <<= 1;
        if (field.kind == ParticleFieldKind::Working) return;
        for (const auto* component : componentsOf(a)) {
            const std::size_t size = component->size();
            if (!(size == n || (size == 0 && field.kind == ParticleFieldKind::Optional)))
                consistent = false;
        }
    });
    if (!consistent) r.reject("corrupt checkpoint: particle arrays of different lengths");
    // An optional field saved with values was on.
    p.keepOptionalFields(optionalOn);
}

std::size_t savedBytesPerParticle() {
    std::size_t bytes = 0;
    ParticleStore().forEachField([&](const ParticleFieldInfo& field, const auto& a) {
        if (field.kind == ParticleFieldKind::Working) return;
        for (const auto* component : componentsOf(a))
            bytes += sizeof(ValueType<decltype(component)>);
    });
    return bytes;
}

std::vector<SavedArray> savedArrays(const ParticleStore& p) {
    std::vector<SavedArray> arrays;
    p.forEachField([&](const ParticleFieldInfo& field, const auto& a) {
        if (field.kind == ParticleFieldKind::Working) return;
        const bool kept =
            field.kind != ParticleFieldKind::Optional ||
            p.kept(static_cast<ParticleField>(&field - ParticleStore::fields().data()));
        for (const auto* component : componentsOf(a))
            arrays.push_back({component->empty() ? nullptr : component->data(),
                              sizeof(ValueType<decltype(component)>), kept});
    });
    return arrays;
}

}  // namespace pbf::detail
