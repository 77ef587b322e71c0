// Neighbour search on the sparse grid (cell size = kernel radius h).
//
// Each step: `sortByCell` computes every particle's cell key (bricks in
// Morton order, rows of cells inside: core/cell_key.hpp) and a stable radix
// sort by key, giving the
// permutation that the caller applies with ParticleStore::reorder; the
// occupied cells become a sorted list with start offsets (backend/sparse_grid.hpp).
// After the reorder the particles of a cell are contiguous, and
// `buildNeighborLists` collects, for every particle, the indices of all
// others closer than h (SIMD distance tests) into per-block lists that all
// solver iterations reuse. Each occupied cell finds its neighbour cells once,
// while the lists of its particles are built. Nothing is sized by the
// domain: memory and time follow the particles.
//
// Positions beyond the key's range are clamped to its border cells. Clamping
// is monotone and never moves two points further apart in cell coordinates,
// so two particles closer than h always land in the same or adjacent cells
// and the search stays exact for them too.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <vector>

#include "backend/sparse_grid.hpp"
#include "core/cell_key.hpp"
#include "core/radix_sort.hpp"
#include "pbf/core/particles.hpp"
#include "pbf/core/vec3.hpp"

namespace pbf {

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
    // Cells of edge `radius` whose coordinates start at the domain's lowest
    // corner. Throws std::invalid_argument if the domain is wider than the
    // cell key holds (2^21 cells a side). `compactSpan` (tests only) is the
    // widest range of indices a block's lists may span and still be stored
    // as 16-bit offsets.
    NeighborSearch(const Aabb& domain, float radius, std::uint32_t compactSpan = 65536);

    float radius() const { return frame_.cell; }
    const cell_key::CellFrame& frame() const { return frame_; }
    std::uint64_t keyOf(const Vec3& p) const { return frame_.keyOf(p); }

    // Stable radix sort of the particles by the cell key of `positions`.
    // Writes perm (new index -> old index); sizes its buffers to the particle
    // count (no allocation once the count stops growing). `scratch`: memory
    // the caller has idle during the sort, for its passes
    // (detail::RadixSort::sort; the CPU solver lends its lambda buffer).
    void sortByCell(const Float3Array& positions, std::vector<std::uint32_t>& perm,
                    std::span<std::byte> scratch = {});
    // After sortByCell: the cell keys of the particles in sorted order, and
    // the occupied cells.
    const std::vector<std::uint64_t>& sortedKeys() const { return keys_; }
    std::size_t occupiedCellCount() const { return cells_.cellKey.size(); }
    grid::SparseGridView gridView() const { return cells_.view(frame_); }

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

    cell_key::CellFrame frame_;
    int keyBits_;  // key bits a cell of the domain can use (what the sort looks at)

    std::vector<std::uint64_t> keys_;  // cell key of each particle, sorted in place
    detail::RadixSort sort_;
    grid::SparseCells cells_;
    // Per thread: the neighbourhoods of the cells of the block it works on.
    std::vector<std::vector<grid::CellNeighborhood>> neighborhoods_;
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
