#include "pbf/core/state_guard.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/parallel.hpp"
#include "core/particle_checks.hpp"

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

bool isFinite(const Vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

std::string describeProblem(const Vec3& x, const Vec3& v, double speedLimit) {
    if (!isFinite(x)) return fmt::format("position is not finite ({}, {}, {})", x.x, x.y, x.z);
    if (!isFinite(v)) return fmt::format("velocity is not finite ({}, {}, {})", v.x, v.y, v.z);
    return fmt::format("speed {:.4g} m/s exceeds the limit of {:.4g} m/s (guard.max_speed)",
                       std::sqrt(double(lengthSquared(v))), speedLimit);
}

}  // namespace

double detail::squaredSpeedLimit(double speedLimit) {
    return speedLimit > 0.0 ? speedLimit * speedLimit : std::numeric_limits<double>::infinity();
}

BadParticle detail::describeBadParticle(std::size_t index, std::uint64_t id, const Vec3& x,
                                        const Vec3& v, double speedLimit) {
    BadParticle bad;
    bad.index = index;
    bad.id = id;
    bad.position = x;
    bad.velocity = v;
    bad.problem = describeProblem(x, v, speedLimit);
    return bad;
}

std::optional<BadParticle> findBadParticle(const ParticleStore& p, double speedLimit) {
    const double limit2 = detail::squaredSpeedLimit(speedLimit);
    const FirstBad first =
        detail::parallelSum<FirstBad>(p.size(), [&](std::size_t begin, std::size_t end) {
            FirstBad bad;
            for (std::size_t i = begin; i < end; ++i) {
                if (detail::badParticle(p.position.get(i), p.velocity.get(i), limit2)) {
                    bad.index = i;
                    break;
                }
            }
            return bad;
        });
    if (first.index == std::numeric_limits<std::size_t>::max()) return std::nullopt;
    const std::size_t i = first.index;
    return detail::describeBadParticle(i, p.id[i], p.position.get(i), p.velocity.get(i),
                                       speedLimit);
}

}  // namespace pbf
