// Per-particle terms of the reductions every backend answers (private
// header): the statistics' partial sums (include/pbf/backend/statistics.hpp) and the
// state guard's test (include/pbf/core/state_guard.hpp). PBF_HD and templates
// over the solids' type, so that the host's loops (core/statistics.cpp,
// core/state_guard.cpp) and the GPU backend's reductions compute the same
// values; with the same fixed blocks, added in block order, the same bits.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>

#include "pbf/backend/statistics.hpp"
#include "pbf/core/config.hpp"
#include "pbf/core/solver_constants.hpp"
#include "pbf/core/state_guard.hpp"
#include "pbf/core/vec3.hpp"

namespace pbf::detail {

// The sums and extremes of one block of particles (statistics.cpp).
struct StatisticsPartial {
    double densityError = 0.0;
    double maxDensityError = 0.0;
    double speedSquaredSum = 0.0;
    double maxSpeedSquared = 0.0;
    double px = 0.0, py = 0.0, pz = 0.0;
    std::size_t escaped = 0;
    std::size_t insideSolid = 0;

    PBF_HD StatisticsPartial& operator+=(const StatisticsPartial& o) {
        densityError += o.densityError;
        maxDensityError = std::max(maxDensityError, o.maxDensityError);
        speedSquaredSum += o.speedSquaredSum;
        maxSpeedSquared = std::max(maxSpeedSquared, o.maxSpeedSquared);
        px += o.px;
        py += o.py;
        pz += o.pz;
        escaped += o.escaped;
        insideSolid += o.insideSolid;
        return *this;
    }

    // Adds particle (x, v, density); `solids` may be null.
    template <class Solids>
    PBF_HD void add(const SolverConstants& c, const Aabb& domain, const Solids* solids,
                    float particleRadius, const Vec3& x, const Vec3& v, float density) {
        const double error = std::max(0.0, double(density) / c.restDensity - 1.0);
        densityError += error;
        maxDensityError = std::max(maxDensityError, error);
        const double speed2 = double(v.x) * v.x + double(v.y) * v.y + double(v.z) * v.z;
        speedSquaredSum += speed2;
        maxSpeedSquared = std::max(maxSpeedSquared, speed2);
        px += v.x;
        py += v.y;
        pz += v.z;
        // contains() is false for NaN coordinates, so NaN counts as escaped.
        if (!domain.contains(x)) ++escaped;
        Vec3 normal;
        if (solids && solids->signedDistance(x, particleRadius, normal) < -0.5f * particleRadius)
            ++insideSolid;
    }
};

// The statistics from the partial sums of all particles.
StateStatistics finishStatistics(const StatisticsPartial& total, std::size_t particles,
                                 const SolverConstants& c);

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
BadParticle describeBadParticle(std::size_t index, std::uint32_t id, const Vec3& x, const Vec3& v,
                                double speedLimit);

}  // namespace pbf::detail
