// Rigid placement of a solid: a rotation (unit quaternion) and a translation.
//
// A solid's shape is defined in its own frame; its pose puts it in the
// world: x_world = rotate(orientation, x_local) + position. Solids are
// static today (identity pose for the analytic shapes, the scene's
// rotation/translation for meshes); moving bodies change the pose and
// velocity between steps without touching the shape.
#pragma once

#include <cmath>
#include <numbers>

#include "pbf/core/config.hpp"
#include "pbf/core/vec3.hpp"

namespace pbf {

// Unit quaternion w + (x, y, z).
struct Quat {
    float w = 1.0f;
    float x = 0.0f;
    float y = 0.0f;
    float z = 0.0f;

    PBF_HD constexpr Quat conjugate() const { return {w, -x, -y, -z}; }
    friend constexpr bool operator==(const Quat&, const Quat&) = default;
};

PBF_HD constexpr Quat operator*(const Quat& a, const Quat& b) {
    return {a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z,
            a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
            a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x,
            a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w};
}

// q v q*, written as v + 2 u x (u x v + w v) with u the vector part.
PBF_HD constexpr Vec3 rotate(const Quat& q, const Vec3& v) {
    const Vec3 u{q.x, q.y, q.z};
    const Vec3 t = cross(u, v) + v * q.w;
    return v + cross(u, t) * 2.0f;
}

// Rotation about a unit axis by `radians`.
inline Quat axisAngle(const Vec3& axis, float radians) {
    const float s = std::sin(0.5f * radians);
    return {std::cos(0.5f * radians), axis.x * s, axis.y * s, axis.z * s};
}

// Euler angles in degrees applied about x, then y, then z (the scene
// format's `rotation`): R = Rz Ry Rx.
inline Quat fromEulerDegrees(const Vec3& degrees) {
    const float rad = std::numbers::pi_v<float> / 180.0f;
    return axisAngle({0, 0, 1}, degrees.z * rad) * axisAngle({0, 1, 0}, degrees.y * rad) *
           axisAngle({1, 0, 0}, degrees.x * rad);
}

struct Pose {
    Vec3 position;
    Quat orientation;

    PBF_HD constexpr bool identity() const { return position == Vec3{} && orientation == Quat{}; }
    PBF_HD constexpr Vec3 toWorld(const Vec3& local) const {
        return rotate(orientation, local) + position;
    }
    PBF_HD constexpr Vec3 toLocal(const Vec3& world) const {
        return rotate(orientation.conjugate(), world - position);
    }
    PBF_HD constexpr Vec3 directionToWorld(const Vec3& local) const {
        return rotate(orientation, local);
    }
};

}  // namespace pbf
