// Rigid bodies of a World: what a body is (mass, inertia, its surface as a
// solid) and where it is (its state). The definition is a
// RigidBodyDescription (include/pbf/world/world_def.hpp); the World steps the
// bodies with the fluid (docs/architecture.md, "Rigid bodies").
#pragma once

#include <cstddef>
#include <string>

#include "pbf/core/vec3.hpp"
#include "pbf/geometry/pose.hpp"

namespace pbf {

// The state of a body, SI, world axes: its centre of mass, the orientation
// of its principal axes, the velocity of the centre of mass and the angular
// velocity. Everything a checkpoint needs to continue a body exactly.
struct RigidBodyState {
    Vec3 position;
    Quat orientation;
    Vec3 velocity;
    Vec3 angularVelocity;
};

// What a body is (fixed while the world runs).
struct RigidBodyInfo {
    std::string field;      // "rigid_bodies[2]": how scene files and messages name it
    std::string describe;   // "box 0.1 x 0.1 x 0.1 m", ...
    double mass = 0.0;      // kg
    double volume = 0.0;    // m^3
    Vec3 inertia;           // principal moments of inertia, kg m^2
    std::size_t solid = 0;  // its surface: index in World::solids()
    // The shape's own frame (the one World::solids() queries it in) within
    // the body frame (centre of mass, principal axes): identity for box,
    // sphere and cylinder, the mesh file's frame for a mesh.
    Pose shapeInBody;
    float boundingRadius = 0.0f;  // farthest surface point from the centre of mass, m
};

// The fluid's push on a body, averaged over the last frame: force (N) and
// torque about the centre of mass (N m).
struct RigidBodyLoad {
    Vec3 force;
    Vec3 torque;
};

}  // namespace pbf
