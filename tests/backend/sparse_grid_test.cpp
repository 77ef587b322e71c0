// The sparse grid's neighbour cells (backend/sparse_grid.hpp) against brute
// force: every occupied cell within one cell of another, each once, near
// the key's range ends too.
#include "backend/sparse_grid.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>
#include <vector>

namespace pbf::test {
namespace {

using cell_key::CellCoords;

void expectNeighborhoodsMatchBruteForce(const std::vector<CellCoords>& occupied) {
    std::vector<std::uint64_t> keys;
    for (const CellCoords& c : occupied) keys.push_back(cell_key::cellKey(c));
    std::sort(keys.begin(), keys.end());
    keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
    grid::SparseCells cells;
    cells.build(keys.data(), keys.size());  // one particle per cell
    ASSERT_EQ(cells.cellKey, keys);
    const grid::SparseGridView g =
        cells.view(cell_key::CellFrame::over({0, 0, 0}, 1.0f));
    for (std::uint32_t c = 0; c < keys.size(); ++c) {
        const std::int32_t block = g.findBlock(keys[c] >> grid::kBlockShift);
        ASSERT_GE(block, 0);
        std::int32_t blocks[27];
        grid::blockNeighborhood(g, std::uint32_t(block), blocks);
        grid::CellNeighborhood nb;
        grid::cellNeighborhood(g, c, blocks, nb);
        const CellCoords a = cell_key::cellCoords(keys[c]);
        std::vector<std::uint32_t> expected;
        for (std::uint32_t k = 0; k < keys.size(); ++k) {
            const CellCoords b = cell_key::cellCoords(keys[k]);
            auto near = [](std::uint32_t u, std::uint32_t v) { return (u > v ? u - v : v - u) <= 1; };
            if (near(a.x, b.x) && near(a.y, b.y) && near(a.z, b.z)) expected.push_back(k);
        }
        // All of them, in increasing index order (the order the lists keep):
        // one particle per cell, so the runs' particle ranges are cell
        // indices. Each run is one row (y and z) with its parts at x - 1, x,
        // x + 1.
        std::vector<std::uint32_t> found;
        for (std::uint32_t k = 0; k < nb.count; ++k) {
            ASSERT_LE(nb.lo[k], nb.a[k]);
            ASSERT_LE(nb.a[k], nb.b[k]);
            ASSERT_LE(nb.b[k], nb.hi[k]);
            ASSERT_LT(nb.lo[k], nb.hi[k]);  // no empty run
            const int dy = nb.row[k] % 3 - 1, dz = nb.row[k] / 3 - 1;
            for (std::uint32_t j = nb.lo[k]; j < nb.hi[k]; ++j) {
                const CellCoords b = cell_key::cellCoords(keys[j]);
                const int dx = j < nb.a[k] ? -1 : (j < nb.b[k] ? 0 : 1);
                ASSERT_EQ(int(b.x) - int(a.x), dx) << "run " << k;
                ASSERT_EQ(int(b.y) - int(a.y), dy) << "run " << k;
                ASSERT_EQ(int(b.z) - int(a.z), dz) << "run " << k;
                found.push_back(j);
            }
        }
        ASSERT_EQ(found, expected) << "cell " << a.x << " " << a.y << " " << a.z;
    }
}

TEST(SparseGrid, NeighbourCellsEqualBruteForceInAClump) {
    std::mt19937 rng(11);
    std::uniform_int_distribution<std::uint32_t> u(30, 42);  // across a brick's y and z ends (32)
    std::vector<CellCoords> cells;
    for (int i = 0; i < 900; ++i) cells.push_back({u(rng), u(rng), u(rng)});
    expectNeighborhoodsMatchBruteForce(cells);
}

TEST(SparseGrid, NeighbourCellsEqualBruteForceAcrossRowsAndBricks) {
    std::mt19937 rng(13);
    // x across a row's end (64), y and z across a brick's (32).
    std::uniform_int_distribution<std::uint32_t> x(58, 70), yz(27, 37);
    std::vector<CellCoords> cells;
    for (int i = 0; i < 1500; ++i) cells.push_back({x(rng), yz(rng), yz(rng)});
    expectNeighborhoodsMatchBruteForce(cells);
}

TEST(SparseGrid, NeighbourCellsEqualBruteForceAtTheKeyRangeEnds) {
    std::mt19937 rng(12);
    const std::uint32_t top = cell_key::kCellsPerAxis - 1;
    std::uniform_int_distribution<std::uint32_t> low(0, 5), high(top - 5, top);
    std::vector<CellCoords> cells;
    for (int i = 0; i < 300; ++i) {
        cells.push_back({low(rng), low(rng), low(rng)});
        cells.push_back({high(rng), high(rng), high(rng)});
        cells.push_back({low(rng), high(rng), low(rng)});
    }
    expectNeighborhoodsMatchBruteForce(cells);
}

}  // namespace
}  // namespace pbf::test
