#include "pbf/backend/statistics.hpp"

#include <algorithm>
#include <cmath>

#include "backend/statistics_partial.hpp"
#include "core/parallel.hpp"

namespace pbf {
StateStatistics computeStatistics(const ParticleStore& p, const SolverConstants& c,
                                  const Aabb& domain, const SolidSet* solids,
                                  float particleRadius) {
    const detail::StatisticsPartial total = detail::parallelSum<detail::StatisticsPartial>(
        p.size(), [&](std::size_t begin, std::size_t end) {
            detail::StatisticsPartial s;
            for (std::size_t i = begin; i < end; ++i)
                s.add(c, domain, solids, particleRadius, p.position.get(i), p.velocity.get(i),
                      p.density[i]);
            return s;
        });
    return detail::finishStatistics(total, p.size(), c);
}

StateStatistics detail::finishStatistics(const StatisticsPartial& total, std::size_t particles,
                                         const SolverConstants& c) {
    StateStatistics stats;
    stats.particles = particles;
    if (particles == 0) return stats;
    stats.averageDensityError = total.densityError / double(particles);
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
