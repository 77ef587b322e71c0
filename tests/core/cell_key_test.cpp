// The cell key (core/cell_key.hpp) and the radix sort by it
// (core/radix_sort.hpp) against their definitions, by brute force.
#include "core/cell_key.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <numeric>
#include <random>
#include <span>
#include <vector>

#include "core/radix_sort.hpp"

namespace pbf::test {
namespace {

using cell_key::CellCoords;
constexpr std::uint32_t kTop = cell_key::kCellsPerAxis - 1;

// Bit k of each coordinate at bits 3k (x), 3k + 1 (y), 3k + 2 (z): Morton's
// definition, one bit at a time.
std::uint64_t mortonByBits(CellCoords c) {
    std::uint64_t key = 0;
    for (int k = 0; k < cell_key::kBitsPerAxis; ++k) {
        key |= std::uint64_t((c.x >> k) & 1u) << (3 * k);
        key |= std::uint64_t((c.y >> k) & 1u) << (3 * k + 1);
        key |= std::uint64_t((c.z >> k) & 1u) << (3 * k + 2);
    }
    return key;
}

std::vector<CellCoords> sampleCoords(std::mt19937& rng, int count) {
    std::uniform_int_distribution<std::uint32_t> any(0, kTop), edge(0, 3);
    std::vector<CellCoords> cs = {{0, 0, 0}, {kTop, kTop, kTop}, {kTop, 0, 0}, {0, kTop, 0}};
    for (int i = 0; i < count; ++i) {
        cs.push_back({any(rng), any(rng), any(rng)});
        // Near the range's ends.
        cs.push_back({edge(rng), kTop - edge(rng), edge(rng)});
    }
    return cs;
}

// The key of the cell one step further along each axis is larger (what the
// distributed split's two-corner test relies on).
template <class Key>
void expectGrowsWithEachCoordinate(Key key, const CellCoords& c) {
    EXPECT_LT(key(c), key({c.x + 1, c.y, c.z}));
    EXPECT_LT(key(c), key({c.x, c.y + 1, c.z}));
    EXPECT_LT(key(c), key({c.x, c.y, c.z + 1}));
}

TEST(CellKey, MortonInterleavesTheBitsAndRoundTrips) {
    std::mt19937 rng(1);
    for (const CellCoords& c : sampleCoords(rng, 2000)) {
        const std::uint64_t key = cell_key::mortonKey(c);
        ASSERT_EQ(key, mortonByBits(c));
        ASSERT_LT(key, std::uint64_t{1} << 63);
        ASSERT_EQ(cell_key::mortonCoords(key), c);
    }
}

TEST(CellKey, MortonGrowsWithEachCoordinateAndKeepsAlignedBlocksContiguous) {
    std::mt19937 rng(2);
    std::uniform_int_distribution<std::uint32_t> any(0, kTop - 1);
    for (int i = 0; i < 2000; ++i) {
        const CellCoords c{any(rng), any(rng), any(rng)};
        expectGrowsWithEachCoordinate(cell_key::mortonKey, c);
        // Morton's key >> 6 is the Morton key of the 4x4x4 block.
        EXPECT_EQ(cell_key::mortonKey(c) >> 6, cell_key::mortonKey({c.x >> 2, c.y >> 2, c.z >> 2}));
    }
}

TEST(CellKey, BrickRowsRoundTripGrowWithEachCoordinateAndKeepRowsContiguous) {
    std::mt19937 rng(5);
    for (const CellCoords& c : sampleCoords(rng, 2000)) {
        const std::uint64_t key = cell_key::cellKey(c);
        ASSERT_EQ(cell_key::cellCoords(key), c);
        ASSERT_NE(key, ~std::uint64_t{0});
    }
    std::uniform_int_distribution<std::uint32_t> any(0, kTop - 1);
    for (int i = 0; i < 2000; ++i) {
        const CellCoords c{any(rng), any(rng), any(rng)};
        expectGrowsWithEachCoordinate(cell_key::cellKey, c);
        // A row of 64 cells along x is 64 consecutive keys.
        const CellCoords rowStart{c.x & ~63u, c.y, c.z};
        EXPECT_EQ(cell_key::cellKey(c), cell_key::cellKey(rowStart) + (c.x & 63u));
        EXPECT_EQ(cell_key::cellKey(c) >> 6, cell_key::cellKey(rowStart) >> 6);
    }
    // Inside a brick, rows: x fastest, then z, then y; bricks in Morton order.
    EXPECT_EQ(cell_key::cellKey({1, 0, 0}), 1u);
    EXPECT_EQ(cell_key::cellKey({0, 0, 1}), 64u);
    EXPECT_EQ(cell_key::cellKey({0, 1, 0}), 64u * 32u);
    EXPECT_EQ(cell_key::cellKey({64, 0, 0}), std::uint64_t{1} << 16);
    EXPECT_EQ(cell_key::cellKey({0, 32, 0}), std::uint64_t{2} << 16);
    EXPECT_EQ(cell_key::cellKey({0, 0, 32}), std::uint64_t{4} << 16);
    const std::uint32_t top = cell_key::kCellsPerAxis - 1;
    EXPECT_EQ(cell_key::cellCoords(cell_key::cellKey({top, top, top})),
              (CellCoords{top, top, top}));
}

TEST(CellKey, HilbertRoundTripsAndStepsToAFaceNeighbour) {
    std::mt19937 rng(3);
    for (const CellCoords& c : sampleCoords(rng, 1000))
        ASSERT_EQ(cell_key::hilbertCoords(cell_key::hilbertKey(c)), c);
    // Consecutive keys are cells that share a face: the curve's defining property.
    std::uniform_int_distribution<std::uint64_t> key(0, (std::uint64_t{1} << 63) - 2);
    for (int i = 0; i < 5000; ++i) {
        const std::uint64_t k = i < 100 ? std::uint64_t(i) : key(rng);
        const CellCoords a = cell_key::hilbertCoords(k), b = cell_key::hilbertCoords(k + 1);
        const long d = std::labs(long(a.x) - long(b.x)) + std::labs(long(a.y) - long(b.y)) +
                       std::labs(long(a.z) - long(b.z));
        ASSERT_EQ(d, 1) << "key " << k;
        ASSERT_EQ(cell_key::hilbertKey(a), k);
    }
}

TEST(CellKey, DomainFramesUseTheBitsTheirCellsNeed) {
    cell_key::CellFrame f;
    ASSERT_TRUE(cell_key::domainFrame({{0, 0, 0}, {1.6f, 1.0f, 0.4f}}, 0.02f, f));
    EXPECT_EQ(f.maxCoordinate, 127u);  // 80 cells: 2 x 4 x 4 bricks
    // The highest corner's key: brick (1, 3, 3) = Morton 0b111'111 after 16 bits.
    EXPECT_EQ(cell_key::keyBits(f.maxCoordinate + 1), 22);
    EXPECT_EQ(cell_key::keyBits(1), 0);
    // The key's axes: rows along the shortest side (z), the longest (x)
    // slowest (the key's y), the middle one (y) as the key's z.
    EXPECT_EQ(f.axis[0], 2);
    EXPECT_EQ(f.axis[1], 0);
    EXPECT_EQ(f.axis[2], 1);
    EXPECT_EQ(f.coords({1.51f, 0.51f, 0.11f}), (CellCoords{5, 75, 25}));
    EXPECT_EQ(f.keyAxes({1, 2, 3}), (pbf::Vec3{3, 1, 2}));
    // Beyond the key's range, or no extent: refused.
    EXPECT_FALSE(cell_key::domainFrame({{0, 0, 0}, {5e4f, 1, 1}}, 0.02f, f));
    EXPECT_FALSE(cell_key::domainFrame({{0, 0, 0}, {1, 0, 1}}, 0.02f, f));
    // Below the origin and beyond the last cell: the border cells (a cube:
    // key x, y, z are the world's x, z, y).
    ASSERT_TRUE(cell_key::domainFrame({{-1, -1, -1}, {1, 1, 1}}, 0.5f, f));
    EXPECT_EQ(f.coords({-3, 0.1f, 7}), (CellCoords{0, f.maxCoordinate, 2}));
}

TEST(RadixSort, EqualsAStableSortForAnyWidthAndThreadCount) {
    std::mt19937_64 rng(4);
    for (int bits : {1, 5, 11, 12, 21, 33, 63}) {
        for (std::size_t n :
             {std::size_t{0}, std::size_t{1}, std::size_t{1000}, std::size_t{200000}}) {
            // Few distinct keys: many ties, whose input order must be kept.
            const std::uint64_t mask = bits == 64 ? ~0ull : (std::uint64_t{1} << bits) - 1;
            std::vector<std::uint64_t> distinct(50);
            for (auto& d : distinct) d = rng() & mask;
            std::vector<std::uint64_t> keys(n);
            for (auto& k : keys) k = distinct[rng() % distinct.size()];
            std::vector<std::uint32_t> expected(n);
            std::iota(expected.begin(), expected.end(), 0u);
            std::stable_sort(expected.begin(), expected.end(),
                             [&](std::uint32_t a, std::uint32_t b) { return keys[a] < keys[b]; });
            // In place, with the sort's own scratch and with a lent one.
            for (const bool lent : {false, true}) {
                detail::RadixSort sort;
                std::vector<std::uint64_t> sorted = keys;
                std::vector<std::uint32_t> perm(n);
                std::vector<std::uint64_t> scratch(n * 3 / 2 + 1);  // 12 bytes a key, aligned
                sort.sort(
                    sorted.data(), n, bits, perm.data(),
                    lent ? std::as_writable_bytes(std::span(scratch)) : std::span<std::byte>{});
                ASSERT_EQ(perm, expected) << bits << " bits, " << n << " keys";
                for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(sorted[i], keys[perm[i]]);
            }
        }
    }
}

}  // namespace
}  // namespace pbf::test
