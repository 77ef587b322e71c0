// The statistics' per-particle terms (private header; the public side is
// include/pbf/backend/statistics.hpp). PBF_HD and a template over the solids'
// type, so that the host's loop (backend/statistics.cpp) and the GPU
// backend's reduction compute the same values; with the same fixed blocks,
// added in block order, the same bits.
#pragma once

#include <algorithm>
#include <cstddef>

#include "pbf/backend/statistics.hpp"
#include "pbf/core/config.hpp"
#include "pbf/core/solver_constants.hpp"
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

}  // namespace pbf::detail
