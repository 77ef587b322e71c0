// Emitters: nozzles that pour water into a running simulation.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "pbf/core/inlet_buffer.hpp"
#include "pbf/geometry/solids.hpp"
#include "pbf/world/world_def.hpp"

namespace pbf {

// Offsets of the particles of one emitted disc: a square lattice of spacing
// 2 r in the plane across `direction`, within `radius` of the axis, or filling the `width` x
// `height` rectangle of a rectangular nozzle.
std::vector<Vec3> emitterDisc(const EmitterDescription& emitter, float particleRadius);
// The stream speed that carries `flowRate` m^3/s through the nozzle's
// particles (each 8 r^3 of water): flow rate / (sites x (2 r)^2).
float flowSpeed(const EmitterDescription& emitter, float particleRadius);

// What an emitter carries from one substep to the next (saved in checkpoints).
struct EmitterState {
    double travelled = 0.0;     // stream length not yet emitted, m
    std::uint64_t emitted = 0;  // particles emitted so far
};

class Emitter {
  public:
    Emitter(const EmitterDescription& description, const SimulationParams& params);

    // The discs due in the substep [time, time + dt): one disc each time
    // the stream has advanced one particle spacing. Discs start at the nozzle
    // and are placed where the stream front is at the end of the substep.
    // Sites inside solids or outside the domain are skipped. Appends the new
    // particles' positions to `positions`; they all move at velocity().
    void emit(double time, double dt, const SolidSet* solids, std::vector<Vec3>& positions);
    Vec3 velocity() const { return description_.direction * description_.speed; }
    // Whether the nozzle pours at `time` (within its window, budget left).
    bool open(double time) const;
    // The water in front of the nozzle that moves at the stream's velocity
    // (pbf/core/inlet_buffer.hpp): across its opening, from one particle
    // radius behind it to one kernel radius `reach` ahead.
    InletBuffer buffer(float reach) const;

    std::size_t emitted() const { return emitted_; }
    std::size_t discSize() const { return disc_.size(); }
    // Particles per second while active: disc size * speed / spacing.
    double rate() const;

    EmitterState state() const { return {travelled_, emitted_}; }
    void setState(const EmitterState& state) {
        travelled_ = state.travelled;
        emitted_ = static_cast<std::size_t>(state.emitted);
    }

  private:
    EmitterDescription description_;
    std::vector<Vec3> disc_;
    float particleRadius_;
    float spacing_;
    Aabb inside_;             // the solver's collision box
    double travelled_ = 0.0;  // stream length not yet emitted, m
    std::size_t emitted_ = 0;
};

}  // namespace pbf
