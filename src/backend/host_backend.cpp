#include "backend/host_backend.hpp"

#include <stdexcept>

#include "backend/outlets.hpp"

namespace pbf {

void HostBackend::append(std::span<const Vec3> positions, std::span<const Vec3> velocities,
                         float density) {
    if (positions.size() != velocities.size())
        throw std::invalid_argument("Backend::append: positions and velocities differ in length");
    checkParticlesPerProcess(kind(), store_.size(), positions.size());
    for (std::size_t k = 0; k < positions.size(); ++k)
        store_.add(positions[k], velocities[k], density);
}

std::size_t HostBackend::removeInside(std::span<const OutletRegion> outlets) {
    const auto kept = detail::particlesOutside(store_, outlets);
    if (!kept) return 0;
    const std::size_t removed = store_.size() - kept->size();
    store_.keepOnly(*kept);
    return removed;
}

float HostBackend::maxSpeed() const {
    return pbf::maxSpeed(store_);
}

std::optional<BadParticle> HostBackend::findBadParticle(double speedLimit) const {
    return pbf::findBadParticle(store_, speedLimit);
}

StateStatistics HostBackend::statistics(const SolverContext& context) const {
    return computeStatistics(store_, context.constants, context.params.domain, context.solids,
                             context.params.particleRadius);
}

void HostBackend::download(ParticleStore& out) const {
    out = store_;
}

}  // namespace pbf
