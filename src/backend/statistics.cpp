#include "pbf/backend/statistics.hpp"

#include <algorithm>
#include <cmath>

#include "core/parallel.hpp"

namespace pbf {
namespace {

struct Partial {
    double densityError = 0.0;
    double maxDensityError = 0.0;
    double speedSquaredSum = 0.0;
    double maxSpeedSquared = 0.0;
    double px = 0.0, py = 0.0, pz = 0.0;
    std::size_t escaped = 0;
    std::size_t insideSolid = 0;

    Partial& operator+=(const Partial& o) {
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
};

}  // namespace

StateStatistics computeStatistics(const ParticleStore& p, const SolverConstants& c,
                                  const Aabb& domain, const SolidSet* solids,
                                  float particleRadius) {
    const Partial total =
        detail::parallelSum<Partial>(p.size(), [&](std::size_t begin, std::size_t end) {
            Partial s;
            for (std::size_t i = begin; i < end; ++i) {
                const double error = std::max(0.0, double(p.density[i]) / c.restDensity - 1.0);
                s.densityError += error;
                s.maxDensityError = std::max(s.maxDensityError, error);
                const Vec3 v = p.velocity.get(i);
                const double speed2 = double(v.x) * v.x + double(v.y) * v.y + double(v.z) * v.z;
                s.speedSquaredSum += speed2;
                s.maxSpeedSquared = std::max(s.maxSpeedSquared, speed2);
                s.px += v.x;
                s.py += v.y;
                s.pz += v.z;
                // contains() is false for NaN coordinates, so NaN counts as escaped.
                if (!domain.contains(p.position.get(i))) ++s.escaped;
                Vec3 normal;
                if (solids && solids->signedDistance(p.position.get(i), particleRadius, normal) <
                                  -0.5f * particleRadius)
                    ++s.insideSolid;
            }
            return s;
        });
    StateStatistics stats;
    stats.particles = p.size();
    if (p.size() == 0) return stats;
    stats.averageDensityError = total.densityError / double(p.size());
    stats.maxDensityError = total.maxDensityError;
    stats.kineticEnergy = 0.5 * c.particleMass * total.speedSquaredSum;
    stats.maxSpeed = std::sqrt(total.maxSpeedSquared);
    stats.momentum = Vec3{float(total.px * c.particleMass), float(total.py * c.particleMass),
                          float(total.pz * c.particleMass)};
    stats.escaped = total.escaped;
    stats.insideSolid = total.insideSolid;
    return stats;
}

float maxSpeed(const ParticleStore& p) {
    const std::ptrdiff_t n = static_cast<std::ptrdiff_t>(p.size());
    float maxSquared = 0.0f;
#pragma omp parallel for reduction(max : maxSquared) num_threads(threadCount()) schedule(static)
    for (std::ptrdiff_t i = 0; i < n; ++i)
        maxSquared = std::max(maxSquared, lengthSquared(p.velocity.get(i)));
    return std::sqrt(maxSquared);
}

}  // namespace pbf
