// The frame a World keeps its coordinates in: measured from an origin near
// its domain, so that a scene far from (0, 0, 0) is as accurate as one at it.
//
// Positions are floats, whose spacing grows with their size: 7.6 um at
// 100 m, 61 um at 1 km, 1 mm at 10 km. The solver's corrections are
// micrometres per iteration, so measured from a point 10 km away they are
// rounded away and the water no longer rests (docs/performance.md,
// "Precision far from the origin"). A World therefore measures every
// position from its frame's origin: (0, 0, 0) for a domain near the origin
// (within four of its own extents: nothing moves, not a bit), else the
// domain's centre rounded to whole metres (exact in a float up to 16,000 km).
// Its public API (definition, particles, arrays, bodies, motions) speaks
// world coordinates; the solver, the solids and checkpoints use the frame.
#pragma once

#include "pbf/core/vec3.hpp"

namespace pbf {

struct WorldDef;

struct LocalFrame {
    Vec3 origin;  // world position of the frame's (0, 0, 0): whole metres

    bool shifted() const { return !(origin == Vec3{}); }
    // Conversions computed in double and rounded once to float.
    Vec3 toFrame(const Vec3& world) const;
    Vec3 toWorld(const Vec3& local) const;
    Aabb toFrame(const Aabb& world) const { return {toFrame(world.min), toFrame(world.max)}; }
};

// The frame of a World over `domain` (world coordinates).
LocalFrame localFrame(const Aabb& domain);

// `def` with every position in it (domain, fluid blocks, solids, rigid
// bodies, emitters) measured in `frame`; directions, sizes and velocities
// are the same in both.
WorldDef inFrame(const WorldDef& def, const LocalFrame& frame);

}  // namespace pbf
