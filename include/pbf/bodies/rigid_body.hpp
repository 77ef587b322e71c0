// Rigid bodies of a World: what a body is (mass, inertia, its surface as a
// solid) and where it is (its state). The definition is a
// RigidBodyDescription (below; a WorldDef lists them); the World steps the
// bodies with the fluid (docs/architecture.md, "Rigid bodies").
#pragma once

#include <cstddef>
#include <string>

#include "pbf/core/vec3.hpp"
#include "pbf/geometry/pose.hpp"
#include "pbf/geometry/solid_description.hpp"

namespace pbf {

// A rigid body (docs/scenes.md, "rigid_bodies"): a solid shape that moves,
// pushed by the fluid (the reaction of the boundary's corrections: buoyancy
// and drag come out of the solver) and by gravity, colliding with other
// bodies, the solids and the domain walls through Bullet. Box, sphere and
// cylinder are given in world coordinates as solids are; `shape.transform`
// places a mesh (scale, rotation, translation) and its rotation also turns a
// box about its centre. Exactly one of density and mass is given (> 0).
struct RigidBodyDescription {
    SolidDescription shape;    // Box, Sphere, Cylinder or Mesh (a closed mesh)
    float density = 0.0f;      // kg/m^3, (0, 1e5]; 0: use mass
    float mass = 0.0f;         // kg, (0, 1e9]; 0: use density
    Vec3 velocity;             // initial velocity of the centre of mass, m/s
    Vec3 angularVelocity;      // initial angular velocity, rad/s (world axes)
    float friction = 0.5f;     // Coulomb coefficient in contacts, [0, 10]
    float restitution = 0.0f;  // share of the normal speed kept in contacts, [0, 1]
    std::string field;         // "rigid_bodies[0]", for messages (set by validate if empty)
};

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
