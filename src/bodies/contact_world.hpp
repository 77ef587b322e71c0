// Contacts and rigid-body dynamics through Bullet (private header; the only
// part of pbf that includes Bullet: src/bodies/contact_world.cpp).
//
// Why Bullet: a well-kept, deterministic rigid-body engine in Debian
// (libbullet-dev, the one Blender uses), with contact generation for boxes,
// spheres, cylinders, convex hulls and triangle meshes and a sequential
// impulse solver; not a contact solver of our own. pbf uses the
// double-precision build (bullet-float64).
//
// Bodies collide with each other, with the static solids and with the six
// walls of the domain. The fluid's force and torque come in from outside
// (World, through the backend's reactions); gravity is Bullet's.
//
// Every contact shape is the true surface dilated by one particle radius r,
// so two surfaces in contact stay one particle diameter (2 r) apart: the
// thinnest film of water the particles resolve (each particle keeps r from
// every surface). Without it, particles caught between a body and the floor
// had nowhere to go: the collision pushed them into the wall, the wall
// pushed them back into the body, and they left at tens of m/s.
//
// Determinism across checkpoints: Bullet keeps contact manifolds (warm
// starting) and broadphase structures between steps, which a checkpoint of
// poses and velocities does not hold. reset() rebuilds the dynamics world
// from the bodies' states alone, and the World calls it at the start of
// every frame — in an uninterrupted run as in a resumed one — so a run
// resumed from a frame's checkpoint repeats the same Bullet computations.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "pbf/bodies/rigid_body.hpp"
#include "pbf/core/vec3.hpp"
#include "pbf/geometry/pose.hpp"

namespace pbf::detail {

// A collision shape in plain data.
struct ContactShape {
    enum class Kind { Box, Sphere, Cylinder, ConvexHull, Plane, TriangleMesh };
    Kind kind = Kind::Box;
    Vec3 halfExtents;          // box; cylinder (along y): (radius, half height, radius)
    float radius = 0.0f;       // sphere
    std::vector<Vec3> points;  // convex hull; triangle mesh vertices
    std::vector<std::array<std::uint32_t, 3>> triangles;  // triangle mesh
    Vec3 normal;          // plane: solid where dot(normal, x) < offset
    float offset = 0.0f;  // plane
};

struct StaticCollider {
    ContactShape shape;
    Pose pose;
    std::string field;  // "solids[1]", "the domain walls"
};

struct BodyCollider {
    ContactShape shape;  // in the body frame (centre of mass, principal axes)
    double mass = 0.0;   // kg
    Vec3 inertia;        // principal moments, kg m^2
    float friction = 0.5f;
    float restitution = 0.0f;
    std::string field;  // "rigid_bodies[0]"
};

class ContactWorld {
  public:
    // `dilation` (m): how far every contact shape reaches beyond its true
    // surface (the particle radius; see above).
    ContactWorld(std::vector<StaticCollider> statics, std::vector<BodyCollider> bodies,
                 float dilation);
    ~ContactWorld();
    ContactWorld(const ContactWorld&) = delete;
    ContactWorld& operator=(const ContactWorld&) = delete;

    // Rebuilds the dynamics world with the bodies at `states` and no memory
    // of earlier contacts (see the header comment).
    void reset(std::span<const RigidBodyState> states);
    // Advances the bodies by dt under gravity, the given forces and torques
    // (about the centres of mass, world axes) and the contacts.
    void step(double dt, const Vec3& gravity, std::span<const Vec3> forces,
              std::span<const Vec3> torques);
    // The bodies' states after the last step (or reset).
    void read(std::span<RigidBodyState> states) const;

    // The first pair (body with body, static solid or wall) whose true
    // surfaces overlap by more than `tolerance` metres at the states of the
    // last reset, as "rigid_bodies[1] overlaps solids[0] by 0.01 m"; none
    // when they are all apart.
    std::optional<std::string> firstOverlap(float tolerance) const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace pbf::detail
