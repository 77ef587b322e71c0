// The state guard: stops a run at the first step that produces a bad state
// (a NaN or infinite position or velocity, or a particle faster than any
// speed the scene can physically reach) instead of writing garbage frames.
//
// Simulation calls findBadParticle on its particles before the first substep
// of every frame and after every substep; the scan is one cheap parallel pass
// over positions and velocities and is deterministic (it reports the lowest
// memory index, and the memory order does not depend on the thread count).
// findBadParticle is also the hook for finer checks: a solver stage can call
// it on the arrays it has just written.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>

#include "pbf/particles.hpp"

namespace pbf {

struct Scene;

struct BadParticle {
    std::size_t index = 0;  // memory index (changes every step)
    std::uint32_t id = 0;   // stable id, as in the PLY files
    Vec3 position;
    Vec3 velocity;
    std::string problem;  // "velocity is NaN", "speed 812 m/s exceeds the limit of 97 m/s", ...
};

// The first particle (lowest memory index) whose position or velocity is not
// finite or whose speed exceeds `speedLimit` (m/s; <= 0 disables the speed
// check). Empty when the state is good.
std::optional<BadParticle> findBadParticle(const ParticleStore& particles, double speedLimit);

// The speed limit of a scene, m/s: output.max_speed when set (> 0), else
// output.max_speed_factor * v_ref with v_ref = sqrt(2 |g| D) + the fastest
// initial block velocity, D the domain diagonal: a particle falling freely
// across the whole domain reaches sqrt(2 |g| D), so anything many times
// faster is a blow-up. Without gravity and initial motion, v_ref is the speed
// that crosses the domain in one frame.
double speedLimit(const Scene& scene);

// Thrown by Simulation::advanceFrame when the state guard fires.
class StateError : public std::runtime_error {
  public:
    StateError(const std::string& message, int frameNumber, int substepNumber,
               std::string stageName, BadParticle badParticle)
        : std::runtime_error(message),
          frame(frameNumber),
          substep(substepNumber),
          stage(std::move(stageName)),
          particle(std::move(badParticle)) {}

    int frame;          // frame being computed (1-based, as in frame_NNNNN.ply)
    int substep;        // substep within that frame (1-based; 0: before the first)
    std::string stage;  // where the check ran, e.g. "after solver step"
    BadParticle particle;
};

}  // namespace pbf
