// Inlet buffers: the water in front of an open nozzle moves at the stream's
// velocity. An emitter places each new disc of particles one spacing behind
// the last; where the water ahead lags (slowed by what it runs into, or
// drawn back by surface tension) the new disc lands inside it, and the
// density constraint's correction, divided by a substep, becomes a kick:
// 1-2 m/s for a 0.1-spacing overlap at surface tension's 20 us substeps,
// which flung a fifth of a dripping nozzle's particles away as spray. So
// at the end of every substep the particles within one kernel radius of
// an open nozzle, across its opening, take the stream's velocity (the
// buffer zone of DualSPHysics' inlets, Tafuni et al. 2018): the overlap is
// resolved in position, as the constraint moves them, and never becomes
// velocity. Plain data with host-device tests: every backend drives by them.
#pragma once

#include <cstdint>
#include <span>

#include "pbf/core/config.hpp"
#include "pbf/core/vec3.hpp"

namespace pbf {

struct InletBuffer {
    Vec3 origin;                                // the nozzle's centre
    Vec3 axis{0, -1, 0};                        // the stream's direction, unit length
    Vec3 across{1, 0, 0}, rise{0, 0, 1};        // a rectangular nozzle's axes, unit length
    float behind = 0.0f;                        // m upstream of the nozzle ...
    float ahead = 0.0f;                         // ... to m downstream
    float radius = 0.0f;                        // m; 0: the rectangle of halfWidth x halfHeight
    float halfWidth = 0.0f, halfHeight = 0.0f;  // m
    Vec3 velocity;                              // m/s, the stream's

    PBF_HD constexpr bool contains(const Vec3& x) const {
        const Vec3 offset = x - origin;
        const float along = dot(offset, axis);
        if (along < -behind || along > ahead) return false;
        const Vec3 side = offset - axis * along;
        if (radius > 0.0f) return dot(side, side) <= radius * radius;
        const float a = dot(side, across), b = dot(side, rise);
        return a * a <= halfWidth * halfWidth && b * b <= halfHeight * halfHeight;
    }
    friend constexpr bool operator==(const InletBuffer&, const InletBuffer&) = default;
};

// The velocity of the first of `count` buffers holding x in `velocity`;
// false (velocity untouched) when none does.
PBF_HD constexpr bool bufferVelocity(const InletBuffer* buffers, std::uint32_t count, const Vec3& x,
                                     Vec3& velocity) {
    for (std::uint32_t k = 0; k < count; ++k)
        if (buffers[k].contains(x)) {
            velocity = buffers[k].velocity;
            return true;
        }
    return false;
}

}  // namespace pbf
