// Kernel properties: normalisation, gradient vs finite differences, symmetry.
#include "pbf/core/kernels.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

namespace {

// Integral of f(r) 4 pi r^2 over [0, h] by composite Simpson's rule.
template <class F>
double radialIntegral(F f, double h, int intervals = 20000) {
    const double dr = h / intervals;
    double sum = 0.0;
    for (int k = 0; k <= intervals; ++k) {
        const double r = k * dr;
        const double w = (k == 0 || k == intervals) ? 1.0 : (k % 2 ? 4.0 : 2.0);
        sum += w * f(r) * 4.0 * std::numbers::pi * r * r;
    }
    return sum * dr / 3.0;
}

class KernelTest : public ::testing::TestWithParam<float> {};

TEST_P(KernelTest, Poly6IntegratesToOne) {
    const pbf::Poly6Kernel w = pbf::Poly6Kernel::withRadius(GetParam());
    const double integral =
        radialIntegral([&](double r) { return w.value(float(r * r)); }, GetParam());
    EXPECT_NEAR(integral, 1.0, 1e-4);
}

TEST_P(KernelTest, SpikyIntegratesToOne) {
    const pbf::SpikyKernel w = pbf::SpikyKernel::withRadius(GetParam());
    const double integral = radialIntegral([&](double r) { return w.value(float(r)); }, GetParam());
    EXPECT_NEAR(integral, 1.0, 1e-4);
}

TEST_P(KernelTest, KernelsVanishAtAndBeyondSupport) {
    const float h = GetParam();
    const pbf::Poly6Kernel poly6 = pbf::Poly6Kernel::withRadius(h);
    const pbf::SpikyKernel spiky = pbf::SpikyKernel::withRadius(h);
    EXPECT_EQ(poly6.value(h * h), 0.0f);
    EXPECT_EQ(poly6.value(4.0f * h * h), 0.0f);
    EXPECT_EQ(spiky.value(h), 0.0f);
    const pbf::Vec3 outside{1.5f * h, 0.0f, 0.0f};
    EXPECT_EQ(spiky.gradient(outside, 1.5f * h), (pbf::Vec3{}));
    EXPECT_EQ(spiky.gradient({}, 0.0f), (pbf::Vec3{}));  // no direction at r = 0
    EXPECT_GT(poly6.value(0.0f), 0.0f);
}

TEST_P(KernelTest, SpikyGradientMatchesFiniteDifferences) {
    const double h = GetParam();
    const pbf::SpikyKernel w = pbf::SpikyKernel::withRadius(float(h));
    // Finite differences of the exact kernel in double precision.
    auto valueAt = [&](double x, double y, double z) {
        const double r = std::sqrt(x * x + y * y + z * z);
        return r >= h ? 0.0 : 15.0 / (std::numbers::pi * std::pow(h, 6)) * std::pow(h - r, 3);
    };
    std::mt19937 rng(1);
    std::uniform_real_distribution<double> coordinate(-h, h);
    int tested = 0;
    while (tested < 200) {
        const double x = coordinate(rng), y = coordinate(rng), z = coordinate(rng);
        const double r = std::sqrt(x * x + y * y + z * z);
        if (r > 0.95 * h || r < 0.05 * h) continue;
        const double e = 1e-6 * h;
        const double gx = (valueAt(x + e, y, z) - valueAt(x - e, y, z)) / (2 * e);
        const double gy = (valueAt(x, y + e, z) - valueAt(x, y - e, z)) / (2 * e);
        const double gz = (valueAt(x, y, z + e) - valueAt(x, y, z - e)) / (2 * e);
        const pbf::Vec3 g = w.gradient({float(x), float(y), float(z)}, float(r));
        const double scale = std::sqrt(gx * gx + gy * gy + gz * gz) + 1e-12;
        EXPECT_NEAR(g.x, gx, 2e-4 * scale);
        EXPECT_NEAR(g.y, gy, 2e-4 * scale);
        EXPECT_NEAR(g.z, gz, 2e-4 * scale);
        ++tested;
    }
}

TEST_P(KernelTest, GradientIsAntisymmetricAndValuesAreRadial) {
    const float h = GetParam();
    const pbf::SpikyKernel spiky = pbf::SpikyKernel::withRadius(h);
    const pbf::Poly6Kernel poly6 = pbf::Poly6Kernel::withRadius(h);
    std::mt19937 rng(2);
    std::uniform_real_distribution<float> coordinate(-0.5f * h, 0.5f * h);
    for (int k = 0; k < 100; ++k) {
        const pbf::Vec3 r{coordinate(rng), coordinate(rng), coordinate(rng)};
        const float len = pbf::length(r);
        EXPECT_EQ(spiky.gradient(r, len), -spiky.gradient(-r, len));
        // The gradient points from x_i towards x_j (W decreases outward).
        EXPECT_LT(pbf::dot(spiky.gradient(r, len), r), 0.0f);
        const pbf::Vec3 rotated{r.y, r.z, r.x};
        const float value = poly6.value(pbf::lengthSquared(r));
        EXPECT_NEAR(value, poly6.value(pbf::lengthSquared(rotated)), 1e-4f * value);
    }
}

INSTANTIATE_TEST_SUITE_P(Radii, KernelTest, ::testing::Values(0.01f, 0.04f, 0.1f, 1.0f));

}  // namespace
