// The laplace case's split of the density constraint's force into pair
// forces (src/validate/constraint_pairs.hpp): corrections made from known
// pair terms (lambda_i + lambda_j) grad W must give those pair terms back.
#include "validate/constraint_pairs.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

namespace pbf::validation::detail {
namespace {

// A jittered lattice of 7^3 particles 0.5 mm apart, kernel radius 2 mm (the
// solver's h = 4 particle radii), and random lambdas.
struct Cloud {
    SpikyKernel kernel = SpikyKernel::withRadius(0.002f);
    std::vector<Vec3> x;
    std::vector<std::vector<std::uint32_t>> neighbours;
    std::vector<double> L;
    std::vector<Vec3> a;  // sum_j (L_i + L_j) grad W_ij
};

Cloud cloud() {
    Cloud c;
    std::mt19937 random(7);
    std::uniform_real_distribution<float> jitter(-0.1f, 0.1f);
    std::uniform_real_distribution<double> lambda(0.5e-8, 2e-8);
    const float d = 0.0005f;
    for (int i = 0; i < 7; ++i)
        for (int j = 0; j < 7; ++j)
            for (int k = 0; k < 7; ++k)
                c.x.push_back({d * (float(i) + jitter(random)), d * (float(j) + jitter(random)),
                               d * (float(k) + jitter(random))});
    const std::size_t n = c.x.size();
    c.neighbours.resize(n);
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = 0; j < n; ++j)
            if (i != j && length(c.x[i] - c.x[j]) < c.kernel.h)
                c.neighbours[i].push_back(std::uint32_t(j));
    for (std::size_t i = 0; i < n; ++i) c.L.push_back(lambda(random));
    for (std::size_t i = 0; i < n; ++i) {
        double s[3] = {0.0, 0.0, 0.0};
        for (const std::uint32_t j : c.neighbours[i]) {
            const Vec3 rij = c.x[i] - c.x[j];
            const Vec3 g = c.kernel.gradient(rij, length(rij));
            s[0] += (c.L[i] + c.L[j]) * g.x, s[1] += (c.L[i] + c.L[j]) * g.y;
            s[2] += (c.L[i] + c.L[j]) * g.z;
        }
        c.a.push_back({float(s[0]), float(s[1]), float(s[2])});
    }
    return c;
}

// Catches a wrong transpose (CGLS then does not converge), a lost scale
// (lambdas off by the gradients' 1e13) or a pair term of the wrong sign.
TEST(ConstraintPairs, RecoversTheLambdasOfExactCorrections) {
    const Cloud c = cloud();
    const ConstraintPairs fit = fitConstraintPairs(c.x, c.a, c.neighbours, c.kernel);
    EXPECT_LT(fit.residual, 1e-5);
    double worst = 0.0;
    for (std::size_t i = 0; i < c.L.size(); ++i)
        worst = std::max(worst, std::fabs(fit.L[i] / c.L[i] - 1.0));
    EXPECT_LT(worst, 1e-3);
}

// What the laplace case reads: the force the particles below a plane exert
// on those above it, pair by pair, equals the true one.
TEST(ConstraintPairs, ForceAcrossAPlaneMatchesTheTruePairForces) {
    const Cloud c = cloud();
    const ConstraintPairs fit = fitConstraintPairs(c.x, c.a, c.neighbours, c.kernel);
    const float plane = 0.5f * 6.0f * 0.0005f;
    double fitted = 0.0, truth = 0.0;
    for (std::size_t i = 0; i < c.x.size(); ++i) {
        if (!(c.x[i].y > plane)) continue;
        for (const std::uint32_t j : c.neighbours[i]) {
            if (c.x[j].y > plane) continue;
            const Vec3 rij = c.x[i] - c.x[j];
            const double gy = c.kernel.gradient(rij, length(rij)).y;
            fitted += (fit.L[i] + fit.L[j]) * gy;
            truth += (c.L[i] + c.L[j]) * gy;
        }
    }
    EXPECT_NEAR(fitted / truth, 1.0, 1e-4);
}

TEST(ConstraintPairs, NoCorrectionGivesNoLambdas) {
    Cloud c = cloud();
    for (Vec3& q : c.a) q = {};
    const ConstraintPairs fit = fitConstraintPairs(c.x, c.a, c.neighbours, c.kernel);
    for (const double l : fit.L) EXPECT_EQ(l, 0.0);
}

}  // namespace
}  // namespace pbf::validation::detail
