// The reference neighbour search against brute force (the model in
// stages_vs_reference_test.cpp relies on it).
#include "backend/reference/neighbor_grid.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

namespace pbf::test {
namespace {

TEST(ReferenceNeighborGrid, FindsExactlyThePairsCloserThanTheRadius) {
    const Aabb domain{{0.0f, 0.0f, 0.0f}, {0.3f, 0.2f, 0.25f}};
    const float radius = 0.04f;
    std::mt19937 rng(7);
    // Inside the domain, on its faces and a little outside (clamped to the
    // border cells), so that every stencil clipping case occurs.
    std::uniform_real_distribution<float> ux(-0.02f, 0.32f), uy(-0.02f, 0.22f), uz(-0.02f, 0.27f);
    std::vector<Vec3> x;
    for (int i = 0; i < 1500; ++i) x.push_back({ux(rng), uy(rng), uz(rng)});
    x.push_back({0.0f, 0.0f, 0.0f});
    x.push_back({0.3f, 0.2f, 0.25f});
    x.push_back(x[5]);  // a coincident pair

    reference::NeighborGrid grid(domain, radius);
    grid.build(x);
    std::size_t total = 0;
    for (std::size_t i = 0; i < x.size(); ++i) {
        std::vector<std::uint32_t> expected;
        for (std::size_t j = 0; j < x.size(); ++j)
            if (j != i && lengthSquared(x[i] - x[j]) < radius * radius)
                expected.push_back(static_cast<std::uint32_t>(j));
        const auto found = grid.neighbors(i);
        std::vector<std::uint32_t> got(found.begin(), found.end());
        std::sort(got.begin(), got.end());
        ASSERT_EQ(got, expected) << "particle " << i;
        total += expected.size();
    }
    EXPECT_EQ(grid.totalNeighborCount(), total);
    EXPECT_GT(total, 10 * x.size());  // the test saw real neighbourhoods
}

}  // namespace
}  // namespace pbf::test
