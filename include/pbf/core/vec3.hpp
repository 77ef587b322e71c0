// A small 3-vector of floats: the value type of every position, velocity and
// gradient in pbf. Deliberately plain (no SIMD intrinsics) so that it can be
// used from CUDA and so that the compiler sees straight-line scalar maths.
#pragma once

#include <cmath>

#include "pbf/core/config.hpp"

namespace pbf {

struct Vec3 {
    float x = 0.0f;
    float y = 0.0f;
    float z = 0.0f;

    PBF_HD constexpr Vec3& operator+=(const Vec3& o) {
        x += o.x;
        y += o.y;
        z += o.z;
        return *this;
    }
    PBF_HD constexpr Vec3& operator-=(const Vec3& o) {
        x -= o.x;
        y -= o.y;
        z -= o.z;
        return *this;
    }
    PBF_HD constexpr Vec3& operator*=(float s) {
        x *= s;
        y *= s;
        z *= s;
        return *this;
    }
    PBF_HD constexpr float operator[](int axis) const {
        return axis == 0 ? x : (axis == 1 ? y : z);
    }
    friend constexpr bool operator==(const Vec3&, const Vec3&) = default;
};

PBF_HD constexpr Vec3 operator+(Vec3 a, const Vec3& b) {
    return a += b;
}
PBF_HD constexpr Vec3 operator-(Vec3 a, const Vec3& b) {
    return a -= b;
}
PBF_HD constexpr Vec3 operator-(const Vec3& a) {
    return {-a.x, -a.y, -a.z};
}
PBF_HD constexpr Vec3 operator*(Vec3 a, float s) {
    return a *= s;
}
PBF_HD constexpr Vec3 operator*(float s, Vec3 a) {
    return a *= s;
}
PBF_HD constexpr float dot(const Vec3& a, const Vec3& b) {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}
PBF_HD constexpr Vec3 cross(const Vec3& a, const Vec3& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
PBF_HD constexpr float lengthSquared(const Vec3& a) {
    return dot(a, a);
}
PBF_HD inline float length(const Vec3& a) {
    return std::sqrt(dot(a, a));
}

// Axis-aligned box [min, max].
struct Aabb {
    Vec3 min;
    Vec3 max;

    PBF_HD constexpr Vec3 extent() const { return max - min; }
    PBF_HD constexpr bool contains(const Vec3& p) const {
        return p.x >= min.x && p.x <= max.x && p.y >= min.y && p.y <= max.y && p.z >= min.z &&
               p.z <= max.z;
    }
    PBF_HD constexpr float volume() const {
        const Vec3 e = extent();
        return e.x * e.y * e.z;
    }
    friend constexpr bool operator==(const Aabb&, const Aabb&) = default;
};

}  // namespace pbf
