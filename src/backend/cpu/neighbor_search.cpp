#include "backend/cpu/neighbor_search.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>

#include "backend/cpu/grid_stencil.hpp"
#include "backend/cpu/simd.hpp"
#include "core/parallel.hpp"

namespace pbf {

NeighborSearch::NeighborSearch(const Aabb& domain, float radius, std::size_t maxCells,
                               std::uint32_t compactSpan)
    : domain_(domain),
      radius_(radius),
      inverseCell_(1.0f / radius),
      compactSpan_(std::min<std::uint32_t>(compactSpan, 65536)) {
    if (!(radius > 0.0f)) throw std::invalid_argument("neighbour search radius must be positive");
    const Vec3 e = domain.extent();
    const double cells = std::ceil(double(e.x) / radius) * std::ceil(double(e.y) / radius) *
                         std::ceil(double(e.z) / radius);
    if (!(cells <= double(maxCells)))
        throw std::invalid_argument(
            "the domain is " + std::to_string(static_cast<long long>(cells)) +
            " grid cells of the kernel radius, more than the limit of " + std::to_string(maxCells) +
            "; use a smaller domain or larger particles");
    // Axes from the shortest extent (fastest, rows) to the longest (see
    // grid_stencil.hpp); ties keep x, y, z order.
    const grid::GridView layout = grid::gridLayout(domain, radius);
    for (int k = 0; k < 3; ++k) {
        axis_[k] = layout.axis[k];
        cells_[k] = layout.n[k];
    }
    cellCount_ = std::size_t{cells_[0]} * cells_[1] * cells_[2];
    cellStart_.assign(cellCount_ + 1, 0);
}

grid::GridView NeighborSearch::gridView() const {
    return {domain_,
            radius_,
            inverseCell_,
            {axis_[0], axis_[1], axis_[2]},
            {cells_[0], cells_[1], cells_[2]},
            cellStart_.data()};
}

std::uint32_t NeighborSearch::cellIndexOf(const Vec3& p) const {
    return gridView().cellIndexOf(p);
}

void NeighborSearch::sortByCell(const Float3Array& positions, std::vector<std::uint32_t>& perm) {
    const std::size_t n = positions.size();
    cellOfParticle_.resize(n);
    perm.resize(n);
    detail::parallelFor(n, [&](std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i)
            cellOfParticle_[i] = cellIndexOf(positions.get(i));
    });
    // Stable counting sort: particles keep their relative order inside a
    // cell, so the result is the same whatever the thread count. The starts
    // serve as the cursors, then move back one cell (no second table).
    std::fill(cellStart_.begin(), cellStart_.end(), 0u);
    for (std::size_t i = 0; i < n; ++i) ++cellStart_[cellOfParticle_[i] + 1];
    for (std::size_t c = 0; c < cellCount_; ++c) cellStart_[c + 1] += cellStart_[c];
    for (std::size_t i = 0; i < n; ++i)
        perm[cellStart_[cellOfParticle_[i]]++] = static_cast<std::uint32_t>(i);
    std::copy_backward(cellStart_.begin(), cellStart_.end() - 1, cellStart_.end());
    cellStart_[0] = 0;
}

void NeighborSearch::buildNeighborLists(const Float3Array& positions) {
    const std::size_t n = positions.size();
    listStart_.resize(n);
    listCount_.resize(n);
    blockCount_ = (n + kListBlockSize - 1) / kListBlockSize;
    if (blocks_.size() < blockCount_) blocks_.resize(blockCount_);
    blockNeighbors_.assign(blockCount_, 0);

    // Each block of particles writes its lists into its own buffer, kept
    // between steps; the lists stay there (no copy into one array). When the
    // indices a block can reach span at most 65536 (most blocks: sorted
    // particles are near their neighbours in memory) the lists store 16-bit
    // offsets from the lowest, halving their memory. Each row is a contiguous candidate range,
    // tested a SIMD vector at a time; the indices of the candidates closer than h are compressed
    // into the list in index order.
    detail::parallelForBlocks(n, kListBlockSize, [&](std::size_t begin, std::size_t end) {
        ListBlock& block = blocks_[begin / kListBlockSize];
        // The stencils of the block's cells (sorted: from the first
        // particle's to the last one's) reach one slab and one row of cells
        // beyond them, so its lists index [lowest, highest).
        const std::size_t reach = std::size_t{cells_[0]} * cells_[1] + cells_[0] + 1;
        const std::size_t firstCell = cellIndexOf(positions.get(begin));
        const std::size_t lastCell = cellIndexOf(positions.get(end - 1));
        const std::uint32_t lowest = cellStart_[firstCell > reach ? firstCell - reach : 0];
        const std::uint32_t highest = cellStart_[std::min(lastCell + reach + 1, cellCount_)];
        block.wide = highest - lowest > compactSpan_;
        block.base = block.wide ? 0 : lowest;
        const std::size_t units = block.wide ? 2 : 1;  // 16-bit units per entry
        std::size_t used = 0;                          // entries
        const grid::GridView grid = gridView();
        for (std::size_t i = begin; i < end;) {
            const grid::ListJob job{grid,
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
            std::size_t candidates = 0;
            grid::forEachStencilRow(
                grid, positions.get(i),
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
    return blockBytes +
           sizeof(std::uint32_t) * (cellOfParticle_.capacity() + cellStart_.capacity() +
                                    listStart_.capacity() + listCount_.capacity()) +
           sizeof(std::size_t) * blockNeighbors_.capacity();
}

}  // namespace pbf
