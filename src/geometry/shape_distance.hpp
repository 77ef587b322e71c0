// Signed distance functions of the solid shapes, written once for every
// backend (private header): the host's Solid classes (geometry/solids.cpp,
// geometry/mesh_solid.cpp) and the device backend's solids
// (backend/gpu/device_solids.hpp) evaluate the same PBF_HD code, so a solid
// is the same surface on the CPU and on a GPU.
//
// Each function returns the signed distance (metres, negative inside) and
// writes the outward unit normal (the normalised gradient of the distance).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>

#include "pbf/core/config.hpp"
#include "pbf/core/vec3.hpp"
#include "pbf/geometry/pose.hpp"

namespace pbf::shape {

// v / |v|, or +y for the zero vector (a point exactly at a centre or on an axis).
PBF_HD inline Vec3 normalised(const Vec3& v) {
    const float len = length(v);
    return len > 0.0f ? v * (1.0f / len) : Vec3{0.0f, 1.0f, 0.0f};
}

PBF_HD inline float boxDistance(const Aabb& box, const Vec3& p, Vec3& normal) {
    const Vec3 centre = (box.min + box.max) * 0.5f;
    const Vec3 half = box.extent() * 0.5f;
    const Vec3 q{std::fabs(p.x - centre.x) - half.x, std::fabs(p.y - centre.y) - half.y,
                 std::fabs(p.z - centre.z) - half.z};
    const Vec3 sign{p.x < centre.x ? -1.0f : 1.0f, p.y < centre.y ? -1.0f : 1.0f,
                    p.z < centre.z ? -1.0f : 1.0f};
    const Vec3 outside{std::max(q.x, 0.0f), std::max(q.y, 0.0f), std::max(q.z, 0.0f)};
    const float outsideLength = length(outside);
    if (outsideLength > 0.0f) {
        normal = normalised({outside.x * sign.x, outside.y * sign.y, outside.z * sign.z});
        return outsideLength;
    }
    // Inside: the nearest face.
    if (q.x >= q.y && q.x >= q.z) {
        normal = {sign.x, 0.0f, 0.0f};
        return q.x;
    }
    if (q.y >= q.z) {
        normal = {0.0f, sign.y, 0.0f};
        return q.y;
    }
    normal = {0.0f, 0.0f, sign.z};
    return q.z;
}

PBF_HD inline float sphereDistance(const Vec3& centre, float radius, const Vec3& p, Vec3& normal) {
    const Vec3 d = p - centre;
    normal = normalised(d);
    return length(d) - radius;
}

// Half-space below the plane through `point` with unit normal `unitNormal`.
PBF_HD inline float planeDistance(const Vec3& point, const Vec3& unitNormal, const Vec3& p,
                                  Vec3& normal) {
    normal = unitNormal;
    return dot(p - point, unitNormal);
}

// Whether p lies within `reach` of the box (a solid's bounds): only then
// can the solid be nearer than reach.
PBF_HD inline bool withinReach(const Aabb& box, const Vec3& p, float reach) {
    return p.x >= box.min.x - reach && p.x <= box.max.x + reach && p.y >= box.min.y - reach &&
           p.y <= box.max.y + reach && p.z >= box.min.z - reach && p.z <= box.max.z + reach;
}

// A shape placed by its pose (`identity`: the identity pose, the shape is
// queried directly): the signed distance in the shape's frame, the normal
// turned back into the world's.
template <class Shape>
PBF_HD float posedDistance(const Shape& shape, bool identity, const Pose& pose, const Vec3& p,
                           Vec3& normal) {
    if (identity) return shape.signedDistance(p, normal);
    Vec3 localNormal;
    const float d = shape.signedDistance(pose.toLocal(p), localNormal);
    normal = pose.directionToWorld(localNormal);
    return d;
}

// The nearest of several solids within `reach` of p, offered one by one in
// index order (the first nearest is kept). SolidSet::signedDistance on the
// host and the GPU backend's DeviceSolids::signedDistance both search with
// it, so a particle meets the same solid on either.
struct NearestSolid {
    float distance;  // the reach until a solid lies nearer
    Vec3 normal;
    std::size_t solid = 0;
    bool found = false;

    PBF_HD explicit NearestSolid(float reach) : distance(reach) {}

    // Solid k, within `bounds`, whose signed distance is
    // solids.distanceTo(k, p, normal).
    template <class Solids>
    PBF_HD void offer(const Solids& solids, std::size_t k, const Aabb& bounds, const Vec3& p,
                      float reach) {
        if (!withinReach(bounds, p, reach)) return;
        Vec3 n;
        const float d = solids.distanceTo(k, p, n);
        if (d < distance) {
            distance = d;
            normal = n;
            solid = k;
            found = true;
        }
    }

    // The distance; the normal and *nearest are written only when a solid
    // lay within reach.
    PBF_HD float result(Vec3& n, std::size_t* nearest) const {
        if (found) {
            n = normal;
            if (nearest) *nearest = solid;
        }
        return distance;
    }
};

// A unit vector perpendicular to the unit `axis`.
PBF_HD inline Vec3 perpendicularTo(const Vec3& axis) {
    return normalised(std::fabs(axis.x) < 0.9f ? cross(axis, {1, 0, 0}) : cross(axis, {0, 1, 0}));
}

// Capped cylinder from `base` along the unit `axis` for `height`: the exact
// distance in (radial, axial) coordinates.
PBF_HD inline float cylinderDistance(const Vec3& base, const Vec3& axis, float radius, float height,
                                     const Vec3& p, Vec3& normal) {
    const Vec3 d = p - base;
    const float along = dot(d, axis);
    const Vec3 radialVector = d - axis * along;
    const float radial = length(radialVector);
    const Vec3 radialDirection =
        radial > 0.0f ? radialVector * (1.0f / radial) : perpendicularTo(axis);
    const float halfHeight = 0.5f * height;
    const float qa = std::fabs(along - halfHeight) - halfHeight;  // axial
    const float qr = radial - radius;                             // radial
    const Vec3 axialDirection = along < halfHeight ? -axis : axis;
    if (qa > 0.0f && qr > 0.0f) {
        const float distance = std::sqrt(qa * qa + qr * qr);
        normal = normalised(radialDirection * qr + axialDirection * qa);
        return distance;
    }
    if (qa > qr) {
        normal = axialDirection;
        return qa;
    }
    normal = radialDirection;
    return qr;
}

// Trilinear interpolation of the 8 samples v[a][b][c] around a point at
// fractions (fx, fy, fz) of its voxel, and the gradient of the interpolant
// (in units of the samples per voxel) from the same lookups: along z, then
// y, then x, keeping the partial derivatives.
PBF_HD inline float trilinearWithGradient(const float v[2][2][2], float fx, float fy, float fz,
                                          Vec3& gradient) {
    const auto lerp = [](float x0, float x1, float t) { return x0 + t * (x1 - x0); };
    float vz[2][2], dz[2][2];
    for (int a = 0; a < 2; ++a)
        for (int b = 0; b < 2; ++b) {
            vz[a][b] = lerp(v[a][b][0], v[a][b][1], fz);
            dz[a][b] = v[a][b][1] - v[a][b][0];
        }
    const float vy0 = lerp(vz[0][0], vz[0][1], fy), vy1 = lerp(vz[1][0], vz[1][1], fy);
    const float dy0 = vz[0][1] - vz[0][0], dy1 = vz[1][1] - vz[1][0];
    const float dz0 = lerp(dz[0][0], dz[0][1], fy), dz1 = lerp(dz[1][0], dz[1][1], fy);
    gradient = {vy1 - vy0, lerp(dy0, dy1, fx), lerp(dz0, dz1, fx)};
    return lerp(vy0, vy1, fx);
}

// Samples of a scalar field at the nodes origin + (i, j, k) * spacing of a
// box, x fastest: a mesh's distance field, a body's boundary-density ratio.
struct GridSamples {
    Vec3 origin;
    float inverseSpacing = 0.0f;
    int nx = 0, ny = 0, nz = 0;
    const float* values = nullptr;

    PBF_HD float at(int i, int j, int k) const {
        return values[(static_cast<long long>(k) * ny + j) * nx + i];
    }
    // Trilinear value at p, `outside` where p is not inside the nodes' box.
    PBF_HD float interpolate(const Vec3& p, float outside) const {
        const Vec3 g = (p - origin) * inverseSpacing;
        if (!(g.x >= 0.0f && g.y >= 0.0f && g.z >= 0.0f)) return outside;
        const int i = int(g.x), j = int(g.y), k = int(g.z);
        if (i >= nx - 1 || j >= ny - 1 || k >= nz - 1) return outside;
        const float fx = g.x - float(i), fy = g.y - float(j), fz = g.z - float(k);
        const auto lerp = [](float a, float b, float t) { return a + t * (b - a); };
        const float x00 = lerp(at(i, j, k), at(i + 1, j, k), fx);
        const float x10 = lerp(at(i, j + 1, k), at(i + 1, j + 1, k), fx);
        const float x01 = lerp(at(i, j, k + 1), at(i + 1, j, k + 1), fx);
        const float x11 = lerp(at(i, j + 1, k + 1), at(i + 1, j + 1, k + 1), fx);
        return lerp(lerp(x00, x10, fy), lerp(x01, x11, fy), fz);
    }
    // A distance field's value and outward normal at p (trilinearWithGradient);
    // beyond the nodes' box `outside`, with the normal of a constant field
    // (normalised(0): +y), as a level set's background value gives.
    PBF_HD float distance(const Vec3& p, float outside, Vec3& normal) const {
        const Vec3 g = (p - origin) * inverseSpacing;
        const int i = int(g.x), j = int(g.y), k = int(g.z);
        if (!(g.x >= 0.0f && g.y >= 0.0f && g.z >= 0.0f) || i >= nx - 1 || j >= ny - 1 ||
            k >= nz - 1) {
            normal = {0.0f, 1.0f, 0.0f};
            return outside;
        }
        float v[2][2][2];
        for (int a = 0; a < 2; ++a)
            for (int b = 0; b < 2; ++b)
                for (int c = 0; c < 2; ++c) v[a][b][c] = at(i + a, j + b, k + c);
        Vec3 gradient;
        const float d =
            trilinearWithGradient(v, g.x - float(i), g.y - float(j), g.z - float(k), gradient);
        normal = normalised(gradient);
        return d;
    }
};

}  // namespace pbf::shape
