// Outlets: regions where water leaves the simulation. A particle whose
// position is in one at the end of a substep is removed (the water that
// reached a channel's end, a drain, the far side of a weir). Plain data with
// host-device tests: every backend, the GPU's included, removes by them.
#pragma once

#include <cstdint>
#include <span>

#include "pbf/core/config.hpp"
#include "pbf/core/vec3.hpp"

namespace pbf {

struct OutletRegion {
    enum class Kind : std::uint32_t {
        Box,        // the particles inside `box` (its faces included) leave
        HalfSpace,  // those past the plane through `point`: (x - point) . normal > 0
    };
    Kind kind = Kind::Box;
    Aabb box;
    Vec3 point;
    Vec3 normal{0, 1, 0};  // unit length

    PBF_HD constexpr bool contains(const Vec3& x) const {
        if (kind == Kind::Box) return box.contains(x);
        return dot(x - point, normal) > 0.0f;
    }
    friend constexpr bool operator==(const OutletRegion&, const OutletRegion&) = default;
};

// Whether x is in any of `count` outlets.
PBF_HD constexpr bool insideAnyOutlet(const OutletRegion* outlets, std::uint32_t count,
                                      const Vec3& x) {
    for (std::uint32_t k = 0; k < count; ++k)
        if (outlets[k].contains(x)) return true;
    return false;
}

inline bool insideAnyOutlet(std::span<const OutletRegion> outlets, const Vec3& x) {
    return insideAnyOutlet(outlets.data(), std::uint32_t(outlets.size()), x);
}

}  // namespace pbf
