// What a solid is, as a scene file or code describes it: plain data that
// the World turns into a Solid (geometry/solids.hpp), and that rigid bodies
// use for their shapes.
#pragma once

#include <string>

#include "pbf/core/vec3.hpp"
#include "pbf/geometry/prescribed_motion.hpp"
#include "pbf/geometry/solids.hpp"

namespace pbf {

// A static solid object (docs/scenes.md, "solids"). Analytic shapes are
// given in world coordinates (identity pose); a mesh's rotation and
// translation are its pose (Transform::pose), its scale is baked into the
// distance field.
struct SolidDescription {
    enum class Kind { Box, Sphere, Plane, Cylinder, Mesh };
    Kind kind = Kind::Box;
    Aabb box;                     // box
    Vec3 center;                  // sphere
    float radius = 0.0f;          // sphere, cylinder
    Vec3 point, normal{0, 1, 0};  // plane
    Vec3 base, axis{0, 1, 0};     // cylinder
    float height = 0.0f;          // cylinder
    std::string file;             // mesh: path of an OBJ file
    Transform transform;          // mesh
    // Wetting with surface tension on (SolidSet::setAdhesion): the work of
    // adhesion in units of 2 sigma, [0, 1]; contact angle acos(2 a - 1).
    float adhesion = 0.0f;
    // A solid's prescribed motion (docs/scenes.md, "Moving solids"); none
    // for a rigid body's shape, which moves by its forces.
    PrescribedMotion motion;
    std::string field;  // "solids[2]", for messages (set by validate if empty)
};

}  // namespace pbf
