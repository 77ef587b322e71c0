// The state guard's per-particle test (private header; the public side is
// include/pbf/core/state_guard.hpp). PBF_HD, so that the host's loop
// (core/state_guard.cpp) and the GPU backend's reduction test the same way.
// The statistics' per-particle terms are one layer up, in
// backend/statistics_partial.hpp.
#pragma once

#include <cmath>
#include <cstddef>
#include <string>

#include "pbf/core/config.hpp"
#include "pbf/core/state_guard.hpp"
#include "pbf/core/vec3.hpp"

namespace pbf::detail {

// The state guard's test (findBadParticle): a NaN or infinity in any
// component makes the sum of the position's components or the squared
// speed non-finite; `!(speed2 <= limit2)` is also true for NaN.
PBF_HD inline bool badParticle(const Vec3& x, const Vec3& v, double limit2) {
    const double vx = v.x, vy = v.y, vz = v.z;
    const double speed2 = vx * vx + vy * vy + vz * vz;
    const double s = double(x.x) + double(x.y) + double(x.z);
    return !std::isfinite(s) || !std::isfinite(speed2) || !(speed2 <= limit2);
}

// The squared speed limit for badParticle (infinite when the limit is off).
double squaredSpeedLimit(double speedLimit);

// The report of bad particle `index` (memory order) with id `id`.
BadParticle describeBadParticle(std::size_t index, std::uint64_t id, const Vec3& x, const Vec3& v,
                                double speedLimit);

}  // namespace pbf::detail
