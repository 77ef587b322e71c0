// The surface-tension cases' measurements on particle clouds
// (src/validate/drops.hpp): the drop a contact angle is measured on is the
// largest connected group, and clustering is read from each particle's
// nearest-neighbour distance.
#include "validate/drops.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

namespace pbf::validation::detail {
namespace {

std::vector<Vec3> lattice(int n, float d, const Vec3& origin) {
    std::vector<Vec3> x;
    for (int k = 0; k < n; ++k)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i)
                x.push_back(origin + Vec3{float(i) * d, float(j) * d, float(k) * d});
    return x;
}

// Catches a "largest" that is the first component or the whole cloud: the
// wetting case then measured a flung particle's height as the drop's.
TEST(DropMeasures, LargestClusterDropsDetachedParticles) {
    std::vector<Vec3> x = lattice(2, 1.0f, {10.0f, 0.0f, 0.0f});          // 8 particles
    const std::vector<Vec3> drop = lattice(3, 1.0f, {0.0f, 0.0f, 0.0f});  // 27
    x.insert(x.end(), drop.begin(), drop.end());
    x.push_back({0.0f, 7.0f, 0.0f});  // a flung particle
    EXPECT_EQ(clusterCount(x, 1.5f), 3u);
    const std::vector<Vec3> largest = largestCluster(x, 1.5f);
    ASSERT_EQ(largest.size(), drop.size());
    for (const Vec3& p : largest) EXPECT_LT(p.x, 5.0f);
    EXPECT_TRUE(largestCluster({}, 1.0f).empty());
}

// On the lattice every particle's nearest neighbour is one spacing away; a
// particle put 0.3 spacings from one site makes exactly those two close.
TEST(DropMeasures, NearestNeighborDistances) {
    std::vector<Vec3> x = lattice(3, 0.5f, {0.0f, 0.0f, 0.0f});
    std::vector<double> nearest = nearestNeighborDistances(x, 1.0f);
    for (const double r : nearest) EXPECT_NEAR(r, 0.5, 1e-6);
    x.push_back(x[13] + Vec3{0.15f, 0.0f, 0.0f});
    nearest = nearestNeighborDistances(x, 1.0f);
    EXPECT_EQ(std::count_if(nearest.begin(), nearest.end(), [](double r) { return r < 0.2; }), 2);
    EXPECT_NEAR(nearest[13], 0.15, 1e-6);
    EXPECT_NEAR(smallestPairDistance(x, 1.0f), 0.15, 1e-6);
    // Alone within the reach: the reach.
    EXPECT_EQ(nearestNeighborDistances({{0.0f, 0.0f, 0.0f}}, 1.0f).front(), 1.0);
}

}  // namespace
}  // namespace pbf::validation::detail
