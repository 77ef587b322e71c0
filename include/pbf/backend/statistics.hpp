// Per-frame statistics of the particle state (the columns of stats.csv).
#pragma once

#include <cstddef>

#include "pbf/core/particles.hpp"
#include "pbf/core/solver_constants.hpp"
#include "pbf/geometry/solids.hpp"

namespace pbf {

struct StateStatistics {
    std::size_t particles = 0;
    // Compression error max(rho_i/rho0 - 1, 0), the quantity PBF drives to
    // zero (under-dense particles at the free surface do not count).
    double averageDensityError = 0.0;
    double maxDensityError = 0.0;
    double kineticEnergy = 0.0;  // J, 1/2 m sum |v|^2
    double maxSpeed = 0.0;       // m/s
    Vec3 momentum;               // kg m/s
    // Particles outside the domain box (or with non-finite positions); must be 0.
    std::size_t escaped = 0;
    // Particles deeper than half a radius inside a solid; must be 0.
    std::size_t insideSolid = 0;
};

// Deterministic: partial sums are combined in a fixed order.
StateStatistics computeStatistics(const ParticleStore& particles, const SolverConstants& constants,
                                  const Aabb& domain, const SolidSet* solids = nullptr,
                                  float particleRadius = 0.0f);

// Largest particle speed (m/s). Deterministic (max does not depend on order).
float maxSpeed(const ParticleStore& particles);

}  // namespace pbf
