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

// The lattice shifts sample the whole cell (Roberts' R3 sequence): 64
// shifts put 4-12 into each of the cell's eight octants (a uniform random
// draw: 8 +- 2.6), and none outside [0, 1). Catches a wrong constant or
// power (shifts along a line or in a plane leave octants empty), and k = 0
// must be no shift (the cases' first sampling is the lattice as it was
// before samplings).
TEST(DropMeasures, LatticeShiftsCoverTheCellEvenly) {
    EXPECT_EQ(lengthSquared(latticeShift(0)), 0.0f);
    int octants[8] = {};
    for (int k = 0; k < 64; ++k) {
        const Vec3 s = latticeShift(k);
        for (const float c : {s.x, s.y, s.z}) {
            EXPECT_GE(c, 0.0f);
            EXPECT_LT(c, 1.0f);
        }
        ++octants[(s.x >= 0.5f) + 2 * (s.y >= 0.5f) + 4 * (s.z >= 0.5f)];
    }
    for (const int n : octants) {
        EXPECT_GE(n, 3);
        EXPECT_LE(n, 13);
    }
}

}  // namespace
}  // namespace pbf::validation::detail
