// Outlets and inlet buffers on particles in host memory (private header):
// shared by the backends whose particles live there.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "pbf/core/inlet_buffer.hpp"
#include "pbf/core/outlet_region.hpp"
#include "pbf/core/particles.hpp"

namespace pbf::detail {

// Indices (ascending) of the particles outside every outlet; nothing when
// every particle stays (the common case costs one scan and no copy).
inline std::optional<std::vector<std::uint32_t>> particlesOutside(
    const ParticleStore& p, std::span<const OutletRegion> outlets) {
    const std::size_t n = p.size();
    std::size_t first = n;
    for (std::size_t i = 0; i < n && !outlets.empty(); ++i)
        if (insideAnyOutlet(outlets, p.position.get(i))) {
            first = i;
            break;
        }
    if (first == n) return std::nullopt;
    std::vector<std::uint32_t> kept;
    kept.reserve(n);
    for (std::size_t i = 0; i < first; ++i) kept.push_back(std::uint32_t(i));
    for (std::size_t i = first + 1; i < n; ++i)
        if (!insideAnyOutlet(outlets, p.position.get(i))) kept.push_back(std::uint32_t(i));
    return kept;
}

// Gives the particles in the inlet buffers their velocity (Backend::driveInside).
inline void driveInside(ParticleStore& p, std::span<const InletBuffer> buffers) {
    if (buffers.empty()) return;
    const auto count = static_cast<std::uint32_t>(buffers.size());
    for (std::size_t i = 0; i < p.size(); ++i) {
        Vec3 v;
        if (bufferVelocity(buffers.data(), count, p.position.get(i), v)) p.velocity.set(i, v);
    }
}

}  // namespace pbf::detail
