#include "pbf/core/state_guard.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/parallel.hpp"

namespace pbf {
namespace {

// Lowest bad index of a block; combining keeps the minimum, so the result is
// the same whatever the thread count.
struct FirstBad {
    std::size_t index = std::numeric_limits<std::size_t>::max();
    FirstBad& operator+=(const FirstBad& o) {
        index = std::min(index, o.index);
        return *this;
    }
};

bool finite(const Vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

std::string describeProblem(const Vec3& x, const Vec3& v, double speedLimit) {
    if (!finite(x)) return fmt::format("position is not finite ({}, {}, {})", x.x, x.y, x.z);
    if (!finite(v)) return fmt::format("velocity is not finite ({}, {}, {})", v.x, v.y, v.z);
    return fmt::format("speed {:.4g} m/s exceeds the limit of {:.4g} m/s (guard.max_speed)",
                       std::sqrt(double(lengthSquared(v))), speedLimit);
}

}  // namespace

std::optional<BadParticle> findBadParticle(const ParticleStore& p, double speedLimit) {
    const double limit2 =
        speedLimit > 0.0 ? speedLimit * speedLimit : std::numeric_limits<double>::infinity();
    const FirstBad first =
        detail::parallelSum<FirstBad>(p.size(), [&](std::size_t begin, std::size_t end) {
            FirstBad bad;
            for (std::size_t i = begin; i < end; ++i) {
                const double vx = p.velocity.x[i], vy = p.velocity.y[i], vz = p.velocity.z[i];
                const double speed2 = vx * vx + vy * vy + vz * vz;
                const double s =
                    double(p.position.x[i]) + double(p.position.y[i]) + double(p.position.z[i]);
                // A NaN or infinity in any component makes s or speed2 non-finite;
                // `!(speed2 <= limit2)` is also true for NaN.
                if (!std::isfinite(s) || !std::isfinite(speed2) || !(speed2 <= limit2)) {
                    bad.index = i;
                    break;
                }
            }
            return bad;
        });
    if (first.index == std::numeric_limits<std::size_t>::max()) return std::nullopt;
    BadParticle bad;
    bad.index = first.index;
    bad.id = p.id[first.index];
    bad.position = p.position.get(first.index);
    bad.velocity = p.velocity.get(first.index);
    bad.problem = describeProblem(bad.position, bad.velocity, speedLimit);
    return bad;
}

}  // namespace pbf
