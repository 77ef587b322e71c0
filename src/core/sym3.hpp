// A symmetric 3 x 3 tensor of floats (six components): the continuum
// surface stress T_i of surface tension (backend/reference/equations.hpp,
// "Continuum surface stress"). Plain and PBF_HD like Vec3, so that the GPU
// kernels store and apply it too (private header).
#pragma once

#include "pbf/core/config.hpp"
#include "pbf/core/vec3.hpp"

namespace pbf {

struct Sym3 {
    float xx = 0.0f, yy = 0.0f, zz = 0.0f, xy = 0.0f, xz = 0.0f, yz = 0.0f;

    // T v.
    PBF_HD constexpr Vec3 operator*(const Vec3& v) const {
        return {xx * v.x + xy * v.y + xz * v.z, xy * v.x + yy * v.y + yz * v.z,
                xz * v.x + yz * v.y + zz * v.z};
    }
    PBF_HD constexpr Sym3 operator+(const Sym3& o) const {
        return {xx + o.xx, yy + o.yy, zz + o.zz, xy + o.xy, xz + o.xz, yz + o.yz};
    }
    PBF_HD constexpr float trace() const { return xx + yy + zz; }
    friend constexpr bool operator==(const Sym3&, const Sym3&) = default;
};

}  // namespace pbf
