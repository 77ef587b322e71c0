#include "backend/cpu/neighbor_search.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "backend/cpu/neighbor_lists.hpp"
#include "backend/cpu/simd.hpp"
#include "core/parallel.hpp"
#include "pbf/core/threading.hpp"

namespace pbf {

NeighborSearch::NeighborSearch(const Aabb& domain, float radius, std::uint32_t compactSpan)
    : compactSpan_(std::min<std::uint32_t>(compactSpan, 65536)) {
    if (!(radius > 0.0f)) throw std::invalid_argument("neighbour search radius must be positive");
    if (!cell_key::domainFrame(domain, radius, frame_))
        throw std::invalid_argument("the domain is more than " +
                                    std::to_string(cell_key::kCellsPerAxis) +
                                    " cells of the kernel radius wide (the cell key's range); "
                                    "use a smaller domain or larger particles");
    keyBits_ = cell_key::keyBits(frame_.maxCoordinate + 1);
}

void NeighborSearch::sortByCell(const Float3Array& positions, std::vector<std::uint32_t>& perm,
                                std::span<std::byte> scratch) {
    const std::size_t n = positions.size();
    keys_.resize(n);
    perm.resize(n);
    detail::parallelFor(n, [&](std::size_t begin, std::size_t end) {
        const cell_key::CellFrame frame = frame_;
        // The arrays in the key's axis order, so that the loop vectorises.
        const float* world[3] = {positions.x.data(), positions.y.data(), positions.z.data()};
        const float *a = world[frame.axis[0]], *b = world[frame.axis[1]], *c = world[frame.axis[2]];
        std::uint64_t* keys = keys_.data();
        for (std::size_t i = begin; i < end; ++i)
            keys[i] = cell_key::cellKey(frame.coordsOfKeyAxes({a[i], b[i], c[i]}));
    });
    // Stable: particles keep their relative order inside a cell, so the
    // result is the same whatever the thread count.
    sort_.sort(keys_.data(), n, keyBits_, perm.data(), scratch);
    cells_.build(keys_.data(), n);
}

void NeighborSearch::buildNeighborLists(const Float3Array& positions) {
    const std::size_t n = positions.size();
    listStart_.resize(n);
    listCount_.resize(n);
    blockCount_ = (n + kListBlockSize - 1) / kListBlockSize;
    if (blocks_.size() < blockCount_) blocks_.resize(blockCount_);
    blockNeighbors_.assign(blockCount_, 0);
    const grid::SparseGridView grid = gridView();
    neighborhoods_.resize(static_cast<std::size_t>(std::max(1, threadCount())));

    // Each block of particles writes its lists into its own buffer, kept
    // between steps; the lists stay there (no copy into one array). When the
    // indices a block can reach span at most 65536 (most blocks: sorted
    // particles are near their neighbours in memory) the lists store 16-bit
    // offsets from the lowest, halving their memory. Each neighbour cell's
    // particles are a contiguous candidate range, tested a SIMD vector at a
    // time; the indices of the candidates closer than h are compressed into
    // the list in index order.
    detail::parallelForBlocks(n, kListBlockSize, [&](std::size_t begin, std::size_t end) {
        ListBlock& block = blocks_[begin / kListBlockSize];
        // The block's cells and their neighbourhoods, once per cell (the
        // blocks of 4^3 cells around them once per such block).
        const std::uint32_t firstCell = static_cast<std::uint32_t>(
            std::upper_bound(cells_.cellStart.begin(), cells_.cellStart.end(),
                             static_cast<std::uint32_t>(begin)) -
            cells_.cellStart.begin() - 1);
        std::vector<grid::CellNeighborhood>& cells =
            neighborhoods_[static_cast<std::size_t>(detail::threadIndex())];
        cells.clear();
        std::uint32_t lowest = static_cast<std::uint32_t>(n), highest = 0;
        std::int32_t blocks[27];
        std::uint64_t blockOfBlocks = ~std::uint64_t{0};
        for (std::uint32_t c = firstCell; c < grid.cellCount && grid.cellStart[c] < end; ++c) {
            const std::uint64_t blockKey = grid.cellKey[c] >> grid::kBlockShift;
            if (blockKey != blockOfBlocks) {
                blockOfBlocks = blockKey;
                grid::blockNeighborhood(grid, static_cast<std::uint32_t>(grid.findBlock(blockKey)),
                                        blocks);
            }
            grid::CellNeighborhood& nb = cells.emplace_back();
            grid::cellNeighborhood(grid, c, blocks, nb);
            for (std::uint32_t k = 0; k < nb.count; ++k) {
                lowest = std::min(lowest, nb.lo[k]);
                highest = std::max(highest, nb.hi[k]);
            }
        }
        block.wide = highest - lowest > compactSpan_;
        block.base = block.wide ? 0 : lowest;
        const std::size_t units = block.wide ? 2 : 1;  // 16-bit units per entry
        std::size_t used = 0;                          // entries
        for (std::size_t i = begin; i < end;) {
            const grid::ListJob job{grid,
                                    cells.data(),
                                    firstCell,
                                    positions.x.data(),
                                    positions.y.data(),
                                    positions.z.data(),
                                    n,
                                    block.wide,
                                    block.base,
                                    block.entries.data(),
                                    block.entries.size(),
                                    listStart_.data(),
                                    listCount_.data()};
            i = grid::collectBlockLists(job, i, end, used);
            if (i == end) break;
            // Particle i's candidates might not fit: grow (rarely, amortised;
            // reserve first: resize alone may double the capacity).
            const auto cell = static_cast<std::uint32_t>(
                std::upper_bound(cells_.cellStart.begin(), cells_.cellStart.end(),
                                 static_cast<std::uint32_t>(i)) -
                cells_.cellStart.begin() - 1);
            std::size_t candidates = 0;
            grid::forEachStencilRange(
                grid, cells[cell - firstCell], positions.get(i),
                [&](std::uint32_t first, std::uint32_t last) { candidates += last - first; });
            const std::size_t needed = units * (used + candidates + simd::kMaxLanes);
            const std::size_t grown = needed + needed / 16 + 1024;
            block.entries.reserve(grown);
            block.entries.resize(grown);
        }
        // Slack past the last list: SIMD loops read it as list entries, so
        // keep it valid (0: the block's base index).
        std::fill_n(block.entries.begin() + static_cast<std::ptrdiff_t>(units * used),
                    units * simd::kMaxLanes, std::uint16_t{0});
        blockNeighbors_[begin / kListBlockSize] = used;
    });
    totalNeighbors_ = 0;
    for (std::size_t b = 0; b < blockCount_; ++b) totalNeighbors_ += blockNeighbors_[b];
}

std::size_t NeighborSearch::compactBlockCount() const {
    std::size_t compact = 0;
    for (std::size_t b = 0; b < blockCount_; ++b) compact += blocks_[b].wide ? 0 : 1;
    return compact;
}

std::size_t NeighborSearch::memoryBytes() const {
    std::size_t blockBytes = 0;
    for (const ListBlock& block : blocks_)
        blockBytes += sizeof(std::uint16_t) * block.entries.capacity();
    for (const auto& cells : neighborhoods_)
        blockBytes += sizeof(grid::CellNeighborhood) * cells.capacity();
    return blockBytes + cells_.memoryBytes() + sort_.memoryBytes() +
           sizeof(std::uint64_t) * keys_.capacity() +
           sizeof(std::uint32_t) * (listStart_.capacity() + listCount_.capacity()) +
           sizeof(std::size_t) * blockNeighbors_.capacity();
}

}  // namespace pbf
