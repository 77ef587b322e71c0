#include "geometry/boundary_scale.hpp"

#include <algorithm>
#include <cmath>

namespace pbf {
namespace {

// Quadrature points of the kernel's ball: the centres of a cubic grid of
// cells h / 8 wide (about 2,100 points inside the ball), each with its poly6
// weight. Cell centres, not corners: the grid nodes sit a whole number of
// particle radii from a face aligned with them (r = h / 4, two cells), and
// corner points would then lie exactly on the face, where the body test
// (signed distance < 0) and the half-space test (offset . n < -s) can round
// differently: at r = 5 mm a whole layer of points counted for the plane
// and not for the body gave a ratio of 0.57 instead of 1 at the centre of a
// cube's face, for the particles resting there.
struct Quadrature {
    std::vector<Vec3> offsets;
    std::vector<float> weights;
};

Quadrature ballQuadrature(float h) {
    Quadrature q;
    constexpr int n = 8;
    const float step = h / float(n);
    const auto at = [&](int i) { return (float(i) + 0.5f) * step; };
    for (int i = -n; i < n; ++i)
        for (int j = -n; j < n; ++j)
            for (int k = -n; k < n; ++k) {
                const Vec3 o{at(i), at(j), at(k)};
                const float r2 = lengthSquared(o);
                if (r2 >= h * h) continue;
                const float d = h * h - r2;
                q.offsets.push_back(o);
                q.weights.push_back(d * d * d);  // poly6 up to its constant
            }
    return q;
}

}  // namespace

BoundaryScale::BoundaryScale(const Solid& shape, float h, float range, float spacing) {
    const Aabb bounds = shape.bounds();
    const Vec3 pad{range + spacing, range + spacing, range + spacing};
    box_ = {bounds.min - pad, bounds.max + pad};
    inverseSpacing_ = 1.0f / spacing;
    const Vec3 e = box_.extent();
    nx_ = int(std::ceil(e.x * inverseSpacing_)) + 1;
    ny_ = int(std::ceil(e.y * inverseSpacing_)) + 1;
    nz_ = int(std::ceil(e.z * inverseSpacing_)) + 1;
    ratio_.assign(std::size_t(nx_) * ny_ * nz_, 1.0f);
    const Quadrature q = ballQuadrature(h);
    for (int k = 0; k < nz_; ++k)
        for (int j = 0; j < ny_; ++j)
            for (int i = 0; i < nx_; ++i) {
                const Vec3 x = box_.min + Vec3{float(i), float(j), float(k)} * spacing;
                Vec3 normal;
                const float s = shape.signedDistance(x, normal);
                // Only where the boundary term acts (0 <= s < range); inside
                // a body the collision, not the density, takes over.
                if (!(s >= 0.0f && s < range + spacing)) continue;
                double body = 0.0, plane = 0.0;
                for (std::size_t m = 0; m < q.offsets.size(); ++m) {
                    const Vec3 y = x + q.offsets[m];
                    Vec3 unused;
                    if (shape.signedDistance(y, unused) < 0.0f) body += q.weights[m];
                    if (dot(q.offsets[m], normal) < -s) plane += q.weights[m];
                }
                if (plane > 0.0)
                    ratio_[(std::size_t(k) * ny_ + j) * nx_ + i] =
                        float(std::min(1.5, body / plane));
            }
}

}  // namespace pbf
