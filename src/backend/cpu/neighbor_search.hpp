// Neighbour search on a sorted uniform grid (cell size = kernel radius h).
//
// Each step: `sortByCell` computes every particle's cell and a stable
// counting sort by cell index, giving the permutation that the caller applies
// with ParticleStore::reorder. After the reorder the particles of cell c are
// the contiguous range [cellStart(c), cellStart(c + 1)), and
// `buildNeighborLists` collects, for every particle, the indices of all
// others closer than h (SIMD distance tests) into per-block lists that all
// solver iterations reuse. Cells are numbered with the domain's shortest
// axis varying fastest and its longest slowest (src/grid_stencil.hpp): rows
// along the shortest axis are adjacent in memory, so the 27-cell stencil is
// read as at most 9 contiguous ranges, and neighbours are near in memory.
//
// Positions outside the grid are clamped to its border cells. Clamping is
// monotone and never moves two points further apart in cell coordinates, so
// two particles closer than h always land in the same or adjacent cells and
// the search stays exact for them too.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <vector>

#include "core/grid_limits.hpp"
#include "pbf/core/particles.hpp"
#include "pbf/core/vec3.hpp"

namespace pbf {

namespace grid {
struct GridView;
}

// One particle's neighbour list. Compact lists (most of them: the indices a
// block of sorted particles reaches span fewer than 65536) store 16-bit
// offsets from `base`; wide ones 32-bit indices. The entries after the list
// are readable (the SIMD loops over-read).
struct NeighborList {
    const std::uint16_t* entries;
    std::uint32_t count;
    std::uint32_t base;
    bool wide;

    std::size_t size() const { return count; }
    std::uint32_t operator[](std::size_t k) const {
        if (wide) {
            std::uint32_t value;
            std::memcpy(&value, entries + 2 * k, sizeof value);
            return value;
        }
        return base + entries[k];
    }
};

class NeighborSearch {
  public:
    // Grid over `domain` with cells of edge `radius`. Throws
    // std::invalid_argument if the grid would need more than `maxCells` cells.
    // `compactSpan` (tests only) is the widest range of indices a block's
    // lists may span and still be stored as 16-bit offsets.
    NeighborSearch(const Aabb& domain, float radius, std::size_t maxCells = kMaxGridCells,
                   std::uint32_t compactSpan = 65536);

    float radius() const { return radius_; }
    std::size_t cellCount() const { return cellCount_; }
    std::uint32_t cellIndexOf(const Vec3& p) const;

    // Planes of cells across the slowest-varying axis (the longest): cells
    // [c * cellsPerPlane(), (c + 1) * cellsPerPlane()) form plane c, so the
    // particles of consecutive planes are consecutive after the sort (a
    // distributed run gives each process a slab of planes).
    std::uint32_t planeCount() const { return cells_[2]; }
    std::size_t cellsPerPlane() const { return std::size_t{cells_[0]} * cells_[1]; }
    std::uint32_t planeOf(const Vec3& p) const {
        return static_cast<std::uint32_t>(cellIndexOf(p) / cellsPerPlane());
    }
    // First sorted index of cell c (c <= cellCount()), valid after sortByCell.
    std::uint32_t cellStart(std::size_t c) const { return cellStart_[c]; }

    // Stable counting sort of the particles by the cell of `positions`.
    // Writes perm (new index -> old index); sizes its buffers to the particle
    // count (no allocation once the count stops growing).
    void sortByCell(const Float3Array& positions, std::vector<std::uint32_t>& perm);

    // Builds neighbour lists from positions already ordered by sortByCell.
    void buildNeighborLists(const Float3Array& positions);

    // The particles closer than h to particle i, in increasing index order.
    NeighborList neighbors(std::size_t i) const {
        const ListBlock& block = blocks_[i / kListBlockSize];
        return {block.entries.data() + listStart_[i], listCount_[i], block.base, block.wide};
    }
    std::size_t totalNeighborCount() const { return totalNeighbors_; }
    // Lists are built for blocks of this many consecutive particles (the
    // blocks of the parallel loops); one block's lists share one width.
    static constexpr std::size_t kListBlockSize = 1024;
    // Blocks whose lists are compact (16-bit), of all blocks.
    std::size_t compactBlockCount() const;
    std::size_t blockCount() const { return blockCount_; }
    // Bytes held by the grid and neighbour lists (for the benchmark's report).
    std::size_t memoryBytes() const;

  private:
    struct ListBlock {
        std::vector<std::uint16_t> entries;  // the block's lists, one after the other
        std::uint32_t base = 0;              // compact entries are offsets from this index
        bool wide = false;
    };

    // The grid as plain data for the stencil code (src/grid_stencil.hpp).
    grid::GridView gridView() const;

    Aabb domain_;
    float radius_;
    float inverseCell_;
    int axis_[3] = {0, 1, 2};  // fastest to slowest varying in the cell index
    std::uint32_t cells_[3];   // cells along axis_[k]
    std::size_t cellCount_;

    std::vector<std::uint32_t> cellOfParticle_;  // cell of each particle, pre-sort order
    std::vector<std::uint32_t> cellStart_;       // size cellCount + 1
    // Neighbour lists, per block of particles; particle i's list starts at
    // listStart_[i] (in 16-bit units) in its block's buffer.
    std::uint32_t compactSpan_;
    std::vector<ListBlock> blocks_;
    std::size_t blockCount_ = 0;
    std::vector<std::uint32_t> listStart_;
    std::vector<std::uint32_t> listCount_;
    std::vector<std::size_t> blockNeighbors_;  // neighbours listed in each block
    std::size_t totalNeighbors_ = 0;
};

}  // namespace pbf
