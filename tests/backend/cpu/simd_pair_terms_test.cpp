// The vector twins of the reference's pair math in the SIMD passes
// (src/backend/cpu/pair_loops-inl.h) against the scalar functions, lane
// for lane. Compiled for the build's static Highway target (the one native
// builds run).
#include <gtest/gtest.h>
#include <hwy/highway.h>

#include <cmath>
#include <cstdint>
#include <ios>
#include <random>
#include <vector>

#include "backend/cpu/simd-inl.h"
// After simd-inl.h, as in the passes.
#include "backend/cpu/pair_loops-inl.h"
#include "pbf/core/params.hpp"
#include "pbf/core/solver_constants.hpp"

namespace pbf::test {
namespace {

namespace hn = hwy::HWY_NAMESPACE;
using namespace pbf::simd::HWY_NAMESPACE;

// spikyGradientFactor is SpikyKernel::gradient's factor bit for bit, given
// the same r^2: the continuum surface stress's SIMD pass
// (surface_stress_pass.cpp) relies on it for its terms to be the
// reference's own (stage_agreement.hpp's bound counts only the sums' order
// and the roundings of r^2). Catches the estimate of 1/r in its place (a
// few ulps off), another coefficient, order of operations, or support
// (pairs at r >= h or r = 0 must give 0, as the scalar kernel's do).
TEST(SimdPairTerms, SpikyGradientFactorIsTheScalarKernelsBitForBit) {
    const SolverConstants c = SolverConstants::from(SimulationParams{});
    const float h = c.h;
    const std::size_t lanes = hn::Lanes(FloatTag{});

    // Neighbours of x_i = 0 spread over [-1.1 h, 1.1 h]^3 (some beyond h),
    // one on the support's edge along an axis and one on x_i itself.
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> coordinate(-1.1f * h, 1.1f * h);
    std::vector<PackedPoint> records;
    records.push_back({h, 0.0f, 0.0f, 0.0f});
    records.push_back({0.0f, 0.0f, 0.0f, 0.0f});
    while (records.size() < 1000)
        records.push_back({coordinate(rng), coordinate(rng), coordinate(rng), 0.0f});
    // A compact list over all of them, with the zeroed slack the passes read.
    std::vector<std::uint16_t> entries(records.size() + lanes, 0);
    for (std::size_t k = 0; k < records.size(); ++k) entries[k] = std::uint16_t(k);
    const NeighborList list{entries.data(), std::uint32_t(records.size()), 0, false};

    const PairConstants k = pairConstants(h, c.poly6.h2);
    const FloatTag d;
    const FloatVec zero = hn::Zero(d);
    std::vector<float> dx(lanes), r2(lanes), factor(lanes);
    std::size_t inSupport = 0;
    for (std::size_t first = 0; first < list.size(); first += lanes) {
        const PairBatch b = loadPairs<false>(k, records.data(), zero, zero, zero, list, first);
        hn::StoreU(b.dx, d, dx.data());
        hn::StoreU(b.r2, d, r2.data());
        hn::StoreU(spikyGradientFactor(k.h, hn::Set(d, c.spiky.gradientCoefficient), b), d,
                   factor.data());
        for (std::size_t lane = 0; lane < lanes; ++lane) {
            if (first + lane >= list.size()) {
                EXPECT_EQ(factor[lane], 0.0f) << "a lane past the list's end";
                continue;
            }
            const PackedPoint& xj = records[first + lane];
            const Vec3 rij{-xj.x, -xj.y, -xj.z};
            const Vec3 expected = c.spiky.gradient(rij, std::sqrt(r2[lane]));
            const float got = dx[lane] * factor[lane];
            // Equal floats: the same bits, but for the sign of a zero term.
            EXPECT_EQ(got, expected.x) << "neighbour " << first + lane << ": " << std::hexfloat
                                       << got << " vs " << expected.x;
            if (expected.x != 0.0f) ++inSupport;
        }
    }
    // Both sides of the support are exercised.
    EXPECT_GT(inSupport, records.size() / 3);
    EXPECT_LT(inSupport, records.size() - records.size() / 10);
}

}  // namespace
}  // namespace pbf::test
