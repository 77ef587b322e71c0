// The state guard: stops a run at the first step that produces a bad state
// (a NaN or infinite position or velocity, or a particle faster than any
// speed the scene can physically reach) instead of writing garbage frames.
//
// World::stepFrame asks its backend for the first bad particle before the
// first substep of every frame and after every substep (a failure is
// returned as a StepError, include/pbf/world/world.hpp); the scan is one cheap parallel pass
// over positions and velocities and is deterministic (it reports the lowest
// memory index, and the memory order does not depend on the thread count).
// findBadParticle is also the hook for finer checks: a solver stage can call
// it on the arrays it has just written.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

#include "pbf/core/particles.hpp"

namespace pbf {

struct BadParticle {
    std::size_t index = 0;  // memory index (changes every step)
    std::uint64_t id = 0;   // stable id, as in the PLY files
    Vec3 position;
    Vec3 velocity;
    std::string problem;  // "velocity is NaN", "speed 812 m/s exceeds the limit of 97 m/s", ...
};

// The first particle (lowest memory index) whose position or velocity is not
// finite or whose speed exceeds `speedLimit` (m/s; <= 0 disables the speed
// check). Empty when the state is good.
std::optional<BadParticle> findBadParticle(const ParticleStore& particles, double speedLimit);

}  // namespace pbf
