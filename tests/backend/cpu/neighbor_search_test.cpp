// The grid neighbour search finds exactly the pairs a brute-force search finds.
#include "backend/cpu/neighbor_search.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

#include "pbf/core/particles.hpp"

namespace {

using pbf::Aabb;
using pbf::Vec3;

std::vector<std::uint32_t> bruteForce(const pbf::Float3Array& x, std::size_t i, float h) {
    std::vector<std::uint32_t> result;
    for (std::size_t j = 0; j < x.size(); ++j) {
        const float dx = x.x[i] - x.x[j], dy = x.y[i] - x.y[j], dz = x.z[i] - x.z[j];
        if (j != i && dx * dx + dy * dy + dz * dz < h * h)
            result.push_back(static_cast<std::uint32_t>(j));
    }
    return result;
}

// `count` points uniform in [lo, hi] of each axis of `box` (as fractions of its extent).
std::vector<Vec3> randomPoints(std::mt19937& rng, std::size_t count, const Aabb& box, float lo,
                               float hi) {
    std::uniform_real_distribution<float> u(lo, hi);
    const Vec3 e = box.extent();
    std::vector<Vec3> points(count);
    for (Vec3& x : points)
        x = {box.min.x + u(rng) * e.x, box.min.y + u(rng) * e.y, box.min.z + u(rng) * e.z};
    return points;
}

// Sorts, reorders and builds lists, then compares every particle's list.
// Counts the blocks whose lists are compact into `compactBlocks`.
void expectMatchesBruteForce(std::vector<Vec3> points, const Aabb& domain, float h,
                             std::uint32_t compactSpan = 65536,
                             std::size_t* compactBlocks = nullptr,
                             std::size_t* blocks = nullptr) {
    pbf::ParticleStore p;
    for (const Vec3& x : points) p.add(x, {}, 1000.0f);
    pbf::NeighborSearch search(domain, h, compactSpan);
    std::vector<std::uint32_t> perm;
    search.sortByCell(p.predicted, perm);
    p.reorder(perm);
    // Sorted by cell: the keys are the particles' and never decrease along
    // the array; inside a cell the particles keep their order (stable).
    for (std::size_t i = 0; i < p.size(); ++i)
        ASSERT_EQ(search.sortedKeys()[i], search.keyOf(p.predicted.get(i)));
    for (std::size_t i = 1; i < p.size(); ++i) {
        ASSERT_LE(search.sortedKeys()[i - 1], search.sortedKeys()[i]);
        if (search.sortedKeys()[i - 1] == search.sortedKeys()[i]) {
            ASSERT_LT(perm[i - 1], perm[i]);
        }
    }
    search.buildNeighborLists(p.predicted);
    std::size_t pairs = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
        const pbf::NeighborList list = search.neighbors(i);
        std::vector<std::uint32_t> found;
        for (std::size_t k = 0; k < list.size(); ++k) found.push_back(list[k]);
        std::sort(found.begin(), found.end());
        ASSERT_EQ(found, bruteForce(p.predicted, i, h)) << "particle " << i;
        pairs += found.size();
    }
    EXPECT_EQ(pairs, search.totalNeighborCount());
    if (compactBlocks) *compactBlocks = search.compactBlockCount();
    if (blocks) *blocks = search.blockCount();
}

const Aabb kUnitBox{{0, 0, 0}, {1, 1, 1}};

TEST(NeighborSearch, RandomPoints) {
    std::mt19937 rng(3);
    std::vector<Vec3> points = randomPoints(rng, 3000, kUnitBox, 0.0f, 1.0f);
    expectMatchesBruteForce(points, kUnitBox, 0.07f);
}

TEST(NeighborSearch, AllInOneCell) {
    std::mt19937 rng(4);
    std::vector<Vec3> points = randomPoints(rng, 500, kUnitBox, 0.50f, 0.55f);
    expectMatchesBruteForce(points, kUnitBox, 0.1f);
}

TEST(NeighborSearch, PointsOnCellBorders) {
    // A lattice whose spacing is half the cell: every other point lies on a
    // cell face, edge or corner, and many pairs sit at exactly h.
    const float h = 0.1f;
    std::vector<Vec3> points;
    for (int i = 0; i <= 10; ++i)
        for (int j = 0; j <= 10; ++j)
            for (int k = 0; k <= 6; ++k)
                points.push_back({float(i) * 0.05f, float(j) * 0.05f, float(k) * 0.05f});
    expectMatchesBruteForce(points, kUnitBox, h);
}

TEST(NeighborSearch, PointsOutsideTheGrid) {
    std::mt19937 rng(5);
    std::vector<Vec3> points = randomPoints(rng, 2000, kUnitBox, -0.5f, 1.5f);
    // Clusters far outside on opposite sides must still see each other only.
    for (int k = 0; k < 20; ++k) points.push_back({-3.0f + 0.01f * float(k), 5.0f, 0.5f});
    for (int k = 0; k < 20; ++k) points.push_back({4.0f, -2.0f + 0.01f * float(k), -7.0f});
    expectMatchesBruteForce(points, kUnitBox, 0.08f);
}

TEST(NeighborSearch, ElongatedDomainsMatch) {
    // Every ordering of the axes' extents, with points inside and outside
    // the domain.
    std::mt19937 rng(8);
    const Aabb boxes[] = {{{0, 0, 0}, {1.0f, 0.3f, 0.6f}},
                          {{-1, 0, 2}, {-0.4f, 1.2f, 2.3f}},
                          {{0, 0, 0}, {0.25f, 0.5f, 1.0f}}};
    for (const Aabb& box : boxes) {
        expectMatchesBruteForce(randomPoints(rng, 2500, box, -0.1f, 1.1f), box, 0.06f);
    }
}

TEST(NeighborSearch, CompactAndWideListsBothMatch) {
    // 5000 points: several blocks of lists. Normally all compact (16-bit
    // offsets); with a tiny allowed span all wide (32-bit indices).
    std::mt19937 rng(6);
    std::vector<Vec3> points = randomPoints(rng, 5000, kUnitBox, 0.0f, 1.0f);
    std::size_t compact = 0, blocks = 0;
    expectMatchesBruteForce(points, kUnitBox, 0.07f, 65536, &compact, &blocks);
    EXPECT_GT(blocks, 1u);
    EXPECT_EQ(compact, blocks);
    expectMatchesBruteForce(points, kUnitBox, 0.07f, 16, &compact, &blocks);
    EXPECT_EQ(compact, 0u);
}

TEST(NeighborSearch, HugeMostlyEmptyDomainsCostWhatTheParticlesCost) {
    // A 60 m x 4 m x 60 m basin at h = 2 cm holds 1.8e9 cells of the kernel
    // radius (a dense cell table of 7 GB); two small clusters in opposite
    // corners need only their own cells.
    const Aabb basin{{0, 0, 0}, {60, 4, 60}};
    std::mt19937 rng(9);
    std::vector<Vec3> points = randomPoints(rng, 1500, {{0, 0, 0}, {0.3f, 0.3f, 0.3f}}, 0, 1);
    for (const Vec3& x : randomPoints(rng, 1500, {{59.7f, 3.7f, 59.7f}, {60, 4, 60}}, 0, 1))
        points.push_back(x);
    expectMatchesBruteForce(points, basin, 0.02f);
    pbf::NeighborSearch search(basin, 0.02f);
    pbf::ParticleStore p;
    for (const Vec3& x : points) p.add(x, {}, 1000.0f);
    std::vector<std::uint32_t> perm;
    search.sortByCell(p.predicted, perm);
    p.reorder(perm);
    search.buildNeighborLists(p.predicted);
    EXPECT_LE(search.occupiedCellCount(), 2u * 4096u);
    EXPECT_LT(search.memoryBytes(), 2000000u);
}

TEST(NeighborSearch, NegativeCoordinatesAndTheKeyRangeEnds) {
    // A domain below the origin, and one exactly as wide as the key holds
    // (2^21 cells) with points at both of its ends.
    std::mt19937 rng(10);
    const Aabb below{{-3, -2, -5}, {-2, -1.5f, -4.2f}};
    expectMatchesBruteForce(randomPoints(rng, 2500, below, -0.05f, 1.05f), below, 0.06f);
    const float h = 0.001f;
    const float side = h * float(pbf::cell_key::kCellsPerAxis) * 0.999f;
    const Aabb widest{{0, 0, 0}, {side, side, side}};
    std::vector<Vec3> ends = randomPoints(rng, 400, {{0, 0, 0}, {0.01f, 0.01f, 0.01f}}, 0, 1);
    for (const Vec3& x :
         randomPoints(rng, 400, {{side - 0.01f, side - 0.01f, side - 0.01f}, {side, side, side}},
                      0, 1.2f))
        ends.push_back(x);
    expectMatchesBruteForce(ends, widest, h);
}

TEST(NeighborSearch, RefusesDomainsBeyondTheKeyRange) {
    // 2^21 cells a side is the key's range: one more is refused.
    const float h = 0.01f;
    const float side = h * float(pbf::cell_key::kCellsPerAxis + 1);
    EXPECT_THROW(pbf::NeighborSearch(Aabb{{0, 0, 0}, {side, 1, 1}}, h), std::invalid_argument);
    EXPECT_THROW(pbf::NeighborSearch(Aabb{{0, 0, 0}, {1, 0, 1}}, h), std::invalid_argument);
}

}  // namespace
