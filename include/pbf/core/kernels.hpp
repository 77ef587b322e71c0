// SPH smoothing kernels used by Position Based Fluids.
//
// Macklin & Mueller 2013, "Position Based Fluids", sec. 3: density is
// estimated with the poly6 kernel and gradients with the spiky kernel
// (Mueller, Charypar & Gross 2003, "Particle-Based Fluid Simulation for
// Interactive Applications"), whose gradient does not vanish at r -> 0 and so
// keeps close particles apart.
//
// Each kernel is a small value type holding its support radius h and the
// precomputed normalisation, so that a stage can take it by value and other
// kernels (e.g. a cubic spline) can be added beside them.
#pragma once

#include <numbers>

#include "pbf/core/config.hpp"
#include "pbf/core/vec3.hpp"

namespace pbf {

// W(r) = 315 / (64 pi h^9) (h^2 - r^2)^3 for r < h; integrates to 1 over R^3.
struct Poly6Kernel {
    float h = 0.0f;
    float h2 = 0.0f;
    float coefficient = 0.0f;

    static Poly6Kernel withRadius(float radius) {
        const double hd = radius;
        const double c =
            315.0 / (64.0 * std::numbers::pi * hd * hd * hd * hd * hd * hd * hd * hd * hd);
        return {radius, radius * radius, static_cast<float>(c)};
    }
    // Takes the squared distance: the density loop never needs a square root.
    PBF_HD float value(float r2) const {
        if (r2 >= h2) return 0.0f;
        const float d = h2 - r2;
        return coefficient * d * d * d;
    }
};

// W(r) = 15 / (pi h^6) (h - r)^3 for r < h; we use its gradient
// grad W(r_vec) = -45 / (pi h^6) (h - r)^2 r_vec / r.
struct SpikyKernel {
    float h = 0.0f;
    float valueCoefficient = 0.0f;
    float gradientCoefficient = 0.0f;  // negative: W decreases with r

    static SpikyKernel withRadius(float radius) {
        const double hd = radius;
        const double h6 = hd * hd * hd * hd * hd * hd;
        return {radius, static_cast<float>(15.0 / (std::numbers::pi * h6)),
                static_cast<float>(-45.0 / (std::numbers::pi * h6))};
    }
    PBF_HD float value(float r) const {
        if (r >= h) return 0.0f;
        const float d = h - r;
        return valueCoefficient * d * d * d;
    }
    // Gradient with respect to x_i of W(x_i - x_j); `rij` = x_i - x_j, `r` = |rij|.
    // Zero at r = 0, where the direction is undefined.
    PBF_HD Vec3 gradient(const Vec3& rij, float r) const {
        if (r >= h || r <= 0.0f) return {};
        const float d = h - r;
        return rij * (gradientCoefficient * d * d / r);
    }
};

}  // namespace pbf
