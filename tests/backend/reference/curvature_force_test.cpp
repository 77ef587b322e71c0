// The curvature force of surface tension (equations.hpp, "Curvature
// force"; Brackbill et al. 1992): its constants, and its two measured
// factors on shapes with a closed-form curvature cut from the rest lattice:
// a flat face (kappa = 0: not pulled), balls (kappa = 2 / R, and the force
// on a half ball sigma 2 pi R, the Laplace pressure 2 sigma / R on its
// equator's area), a rod (kappa = 1 / R) and an ellipsoid (the poles more
// curved than the equator as 2 b / a^2 against 1 / a + a / b^2).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <numbers>
#include <vector>

#include "backend/reference/equations.hpp"
#include "backend/reference/neighbor_grid.hpp"
#include "backend/reference/particle_sums.hpp"
#include "pbf/core/params.hpp"
#include "pbf/core/solver_constants.hpp"

namespace pbf::test {
namespace {

constexpr float kSigma = 0.0728f;

SimulationParams waterParams(float sigma) {
    SimulationParams p;
    p.domain = {{-0.05f, -0.05f, -0.05f}, {0.05f, 0.05f, 0.05f}};
    p.particleRadius = 0.00025f;  // 0.5 mm spacing, as the validation's drops
    p.fluid.surfaceTension = sigma;
    return p;
}

// Catches constants that do not follow equations.hpp (sigma itself, no
// calibration factor; the band's floor 0.2 / d and depth 0.7 d; the
// cohesion's pull at 0.45 of the derivation's with its core kept) or a
// force left on while surface tension is off.
TEST(CurvatureForce, ConstantsFollowTheModel) {
    const SimulationParams p = waterParams(kSigma);
    const SolverConstants c = SolverConstants::from(p);
    const float d = p.particleSpacing();
    EXPECT_EQ(c.surfaceTension, kSigma);
    EXPECT_FLOAT_EQ(c.surfaceFloor, 0.2f / d);
    EXPECT_FLOAT_EQ(c.surfaceOffset, 0.7f * d);
    const SolverConstants off = SolverConstants::from(waterParams(0.0f));
    EXPECT_FLOAT_EQ(c.cohesionCoreScale, off.cohesionCoreScale / 0.45f);
    EXPECT_EQ(off.surfaceTension, 0.0f);
    EXPECT_EQ(off.surfaceFloor, 0.0f);
    EXPECT_EQ(off.surfaceOffset, 0.0f);
}

// The rest lattice's sites (spacing d, a site at the origin) inside a shape.
std::vector<Vec3> latticeInside(float d, int reach, const std::function<bool(const Vec3&)>& in) {
    std::vector<Vec3> x;
    for (int a = -reach; a <= reach; ++a)
        for (int b = -reach; b <= reach; ++b)
            for (int k = -reach; k <= reach; ++k) {
                const Vec3 q{float(a) * d, float(b) * d, float(k) * d};
                if (in(q)) x.push_back(q);
            }
    return x;
}

// Every particle's g, kappa and acceleration (the reference's passes).
struct Field {
    std::vector<Vec3> g, normal, a;
    std::vector<float> kappa;
};

Field curvatureField(const SolverConstants& c, const std::vector<Vec3>& x) {
    reference::NeighborGrid grid({{-0.05f, -0.05f, -0.05f}, {0.05f, 0.05f, 0.05f}}, c.h);
    grid.build(x);
    const std::size_t n = x.size();
    Field f;
    f.g.resize(n), f.normal.resize(n), f.a.resize(n), f.kappa.resize(n);
    for (std::size_t i = 0; i < n; ++i) f.g[i] = reference::colourGradient(c, x, grid.neighbors(i), i);
    for (std::size_t i = 0; i < n; ++i)
        f.normal[i] = reference::bandNormal(c, x, f.g, grid.neighbors(i), i);
    for (std::size_t i = 0; i < n; ++i)
        f.kappa[i] = reference::curvature(c, x, f.g, f.normal, grid.neighbors(i), i);
    for (std::size_t i = 0; i < n; ++i)
        f.a[i] = reference::curvatureForceVelocityChange(c, 1.0f, x, f.g, f.kappa,
                                                         grid.neighbors(i), i);
    return f;
}

bool onBand(const SolverConstants& c, const Vec3& g) {
    return reference::surfaceBandWeight(c, g) > 0.0f;
}

// The A-weighted mean of kappa over the band particles that `where` selects.
double meanKappa(const SolverConstants& c, const std::vector<Vec3>& x, const Field& f,
                 const std::function<bool(const Vec3&)>& where) {
    double sum = 0.0, weight = 0.0;
    for (std::size_t i = 0; i < x.size(); ++i) {
        const float w = reference::surfaceBandWeight(c, f.g[i]);
        if (!(w > 0.0f) || !where(x[i])) continue;
        sum += double(w) * f.kappa[i];
        weight += w;
    }
    return sum / weight;
}

// On a flat face kappa = 0: the middle of a thick slab's top face is not
// pulled, and the bulk (off the band) feels nothing. Catches a kappa biased
// by the band's depth or by a particle's own normal, a floor that lets the
// bulk carry the force, or a force along the normal where nothing curves.
TEST(CurvatureForce, AFlatFaceIsNotPulledAndTheBulkIsFree) {
    const SolverConstants c = SolverConstants::from(waterParams(kSigma));
    const float d = waterParams(kSigma).particleSpacing();
    const std::vector<Vec3> x = latticeInside(d, 12, [&](const Vec3& q) {
        return std::fabs(q.x) <= 12.0f * d && std::fabs(q.z) <= 12.0f * d && q.y <= 0.0f &&
               q.y >= -6.0f * d;
    });
    const Field f = curvatureField(c, x);
    // The pressure a ball of 6 spacings' radius would get, as an acceleration
    // of its band: sigma (2 / R) / (rho0 band depth ~ d).
    const double ball = kSigma * (2.0 / (6.0 * d)) / (c.restDensity * d);
    double face = 0.0, bulk = 0.0;
    std::size_t faceCount = 0;
    for (std::size_t i = 0; i < x.size(); ++i) {
        const bool middle = std::fabs(x[i].x) <= 4.0f * d && std::fabs(x[i].z) <= 4.0f * d;
        if (!middle) continue;
        if (x[i].y == 0.0f) {
            face = std::max(face, double(length(f.a[i])));
            ++faceCount;
            EXPECT_TRUE(onBand(c, f.g[i]));
        } else if (x[i].y < -1.5f * d && x[i].y > -4.5f * d) {  // between the faces
            bulk = std::max(bulk, double(length(f.a[i])));
        }
    }
    std::printf("  face's largest |a| %.3g m/s^2 (%zu particles), bulk's %.3g; a 6 d ball's %.3g\n",
                face, faceCount, bulk, ball);
    EXPECT_EQ(faceCount, 81u);
    EXPECT_LT(face, 1e-3 * ball);
    EXPECT_EQ(bulk, 0.0);
}

// A ball of radius R cut from the lattice: the band's kappa is 2 / R of the
// band's own radius, and the force on the upper half, sigma (2 / R) pi R^2
// for the interface at the particles' volume radius R (Laplace's jump on
// the equator's area), is what holds the drop's pressure. Catches a kappa
// that reads the band's depth (its denominator with |x_ij|^2 for the
// distance across n: 20 % low), a delta that does not integrate to one
// across the band, or the band's depth inside the interface not accounted
// for (both 10-30 % low at these radii).
TEST(CurvatureForce, BallsGetLaplacesForce) {
    const SolverConstants c = SolverConstants::from(waterParams(kSigma));
    const float d = waterParams(kSigma).particleSpacing();
    for (const float spacings : {6.0f, 12.0f}) {
        const float r = spacings * d;
        const std::vector<Vec3> x = latticeInside(
            d, int(spacings) + 1, [&](const Vec3& q) { return length(q) <= r + 0.01f * d; });
        const Field f = curvatureField(c, x);
        const double radius =
            std::cbrt(3.0 * double(x.size()) / (4.0 * std::numbers::pi)) * double(d);
        double upper = 0.0, bandRadius = 0.0, bandWeight = 0.0;
        for (std::size_t i = 0; i < x.size(); ++i) {
            if (x[i].y > 0.0f) upper += double(c.particleMass) * f.a[i].y;
            const float w = reference::surfaceBandWeight(c, f.g[i]);
            bandRadius += double(w) * length(x[i]);
            bandWeight += w;
        }
        bandRadius /= bandWeight;
        const double kappa = meanKappa(c, x, f, [](const Vec3&) { return true; });
        const double pressure = -upper / (std::numbers::pi * radius * radius);
        const double laplace = 2.0 * kSigma / radius;
        std::printf(
            "  ball of %.0f spacings: kappa %.4g 1/m (2 / band radius %.4g, 2 / R %.4g); band "
            "%.2f d inside R; force on the upper half / pi R^2 %.3f Pa, 2 sigma / R %.3f Pa\n",
            spacings, kappa, 2.0 / bandRadius, 2.0 / radius, (radius - bandRadius) / d, pressure,
            laplace);
        EXPECT_NEAR(kappa * bandRadius / 2.0, 1.0, 0.1) << spacings;
        EXPECT_NEAR(pressure / laplace, 1.0, 0.1) << spacings;
    }
}

// A rod of radius R along z (kappa = 1 / R: one curved direction) and an
// ellipsoid of semi-axes b along y and a across: kappa at the poles 2 b / a^2,
// at the equator 1 / a + a / b^2 (the mode-2 shape of the Rayleigh drop).
// Catches a kappa that reads only the sphere's (2 / R whatever the shape),
// or one that averages the two directions wrongly (the rod's would be 2 / R).
TEST(CurvatureForce, KappaFollowsTheShape) {
    const SolverConstants c = SolverConstants::from(waterParams(kSigma));
    const float d = waterParams(kSigma).particleSpacing();
    {
        const float r = 10.0f * d;
        const std::vector<Vec3> x = latticeInside(d, 20, [&](const Vec3& q) {
            return q.x * q.x + q.y * q.y <= r * r + 0.01f * d * d && std::fabs(q.z) <= 20.0f * d;
        });
        const Field f = curvatureField(c, x);
        double band = 0.0, weight = 0.0;
        for (std::size_t i = 0; i < x.size(); ++i) {
            const float w = reference::surfaceBandWeight(c, f.g[i]);
            if (std::fabs(x[i].z) > 8.0f * d) continue;
            band += double(w) * std::hypot(x[i].x, x[i].y);
            weight += w;
        }
        band /= weight;
        const double kappa =
            meanKappa(c, x, f, [&](const Vec3& q) { return std::fabs(q.z) <= 8.0f * d; });
        std::printf("  rod: kappa %.4g 1/m, 1 / band radius %.4g\n", kappa, 1.0 / band);
        EXPECT_NEAR(kappa * band, 1.0, 0.15);
    }
    {
        const float b = 14.0f * d, a = 10.0f * d;
        const std::vector<Vec3> x = latticeInside(d, 15, [&](const Vec3& q) {
            return (q.x * q.x + q.z * q.z) / (a * a) + q.y * q.y / (b * b) <= 1.0f + 1e-4f;
        });
        const Field f = curvatureField(c, x);
        // The band's poles and equator: where n is within 25 degrees of y, or
        // of the equator's plane.
        const auto poles = [&](std::size_t i) {
            return std::fabs(reference::outwardNormal(f.g[i]).y) > 0.9f;
        };
        const auto equator = [&](std::size_t i) {
            return std::fabs(reference::outwardNormal(f.g[i]).y) < 0.25f;
        };
        double kp = 0.0, wp = 0.0, ke = 0.0, we = 0.0;
        for (std::size_t i = 0; i < x.size(); ++i) {
            const float w = reference::surfaceBandWeight(c, f.g[i]);
            if (!(w > 0.0f)) continue;
            if (poles(i)) kp += double(w) * f.kappa[i], wp += w;
            if (equator(i)) ke += double(w) * f.kappa[i], we += w;
        }
        kp /= wp, ke /= we;
        const double theoryPoles = 2.0 * b / (a * a), theoryEquator = 1.0 / a + a / (b * b);
        std::printf("  ellipsoid: kappa at the poles %.4g (%.4g), at the equator %.4g (%.4g)\n",
                    kp, theoryPoles, ke, theoryEquator);
        EXPECT_NEAR((kp - ke) / (theoryPoles - theoryEquator), 1.0, 0.3);
    }
}

}  // namespace
}  // namespace pbf::test
