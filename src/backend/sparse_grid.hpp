// The sparse grid: particles sorted by cell key (core/cell_key.hpp), the
// occupied cells as a sorted list with start offsets, and the stencil walk
// around a particle (private header, PBF_HD: the CPU search, the GPU kernels
// and their tests share it).
//
// Nothing here is sized by the domain. A cell's 26 neighbours are found by
// their 4x4x4 blocks: a block (a cube of 64 cells whose corner coordinates
// are multiples of 4) is one contiguous key range, key >> 6 is its own
// Morton key, and a 64-bit mask says which of its cells hold particles. A
// cell's neighbourhood lies in the 27 blocks around its own, found once per
// block by binary search over the occupied blocks; each neighbour cell is
// then one popcount away. The CPU search does this once per occupied cell
// while it builds the lists, the GPU once per cell into a table.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/cell_key.hpp"
#include "pbf/core/config.hpp"
#include "pbf/core/vec3.hpp"

namespace pbf::grid {

inline constexpr int kBlockShift = 6;  // key bits of the cells inside a 4x4x4 block

PBF_HD inline int popcount64(std::uint64_t v) {
#if defined(__CUDA_ARCH__)
    return __popcll(v);
#else
    return __builtin_popcountll(v);
#endif
}

struct SparseGridView {
    cell_key::CellFrame frame;
    const std::uint64_t* cellKey;    // occupied cells, increasing
    const std::uint32_t* cellStart;  // particles of cell c: [cellStart[c], cellStart[c + 1])
    std::uint32_t cellCount;
    const std::uint64_t* blockKey;        // occupied blocks (cell key >> 6), increasing
    const std::uint32_t* blockFirstCell;  // each block's first occupied cell
    const std::uint64_t* blockMask;       // bit s: the block's cell with key & 63 == s occupied
    std::uint32_t blockCount;

    // Index of the occupied block with this key, or -1.
    PBF_HD std::int32_t findBlock(std::uint64_t key) const {
        std::uint32_t lo = 0, hi = blockCount;
        while (lo < hi) {
            const std::uint32_t mid = lo + (hi - lo) / 2;
            if (blockKey[mid] < key) {
                lo = mid + 1;
            } else {
                hi = mid;
            }
        }
        return lo < blockCount && blockKey[lo] == key ? static_cast<std::int32_t>(lo) : -1;
    }

    // Index of the occupied cell `sub` (key & 63) of block b (-1: none).
    PBF_HD std::int32_t cellInBlock(std::int32_t b, std::uint32_t sub) const {
        if (b < 0) return -1;
        const std::uint64_t mask = blockMask[b];
        if (!((mask >> sub) & 1u)) return -1;
        const std::uint64_t below = mask & ((std::uint64_t{1} << sub) - 1u);
        return static_cast<std::int32_t>(blockFirstCell[b] + std::uint32_t(popcount64(below)));
    }
};

// Offset code of a neighbour: (dx + 1) + 3 (dy + 1) + 9 (dz + 1); 13 is the cell itself.
PBF_HD inline int offsetCode(int dx, int dy, int dz) {
    return (dx + 1) + 3 * (dy + 1) + 9 * (dz + 1);
}

// The 27 blocks around block b (b included, code 13), -1 where none is occupied.
PBF_HD inline void blockNeighborhood(const SparseGridView& g, std::uint32_t b, std::int32_t out[27]) {
    const cell_key::CellCoords c = cell_key::mortonCoords(g.blockKey[b]);
    constexpr std::uint32_t kBlocksPerAxis = cell_key::kCellsPerAxis >> 2;
    for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
                const std::int64_t x = std::int64_t(c.x) + dx, y = std::int64_t(c.y) + dy,
                                   z = std::int64_t(c.z) + dz;
                const bool inside = x >= 0 && y >= 0 && z >= 0 && x < kBlocksPerAxis &&
                                    y < kBlocksPerAxis && z < kBlocksPerAxis;
                out[offsetCode(dx, dy, dz)] =
                    (dx == 0 && dy == 0 && dz == 0)
                        ? static_cast<std::int32_t>(b)
                        : (inside ? g.findBlock(cell_key::mortonKey(
                                        {std::uint32_t(x), std::uint32_t(y), std::uint32_t(z)}))
                                  : -1);
            }
}

// An occupied cell's occupied neighbours (itself included), in increasing
// cell index: the order their particles lie in memory.
struct CellNeighborhood {
    std::uint32_t count;
    std::uint32_t cell[27];
    std::uint8_t offset[27];  // offsetCode of each
};

// The neighbourhood of cell c, given the neighbourhood of its block
// (blockNeighborhood of cellKey[c] >> 6's index).
PBF_HD inline void cellNeighborhood(const SparseGridView& g, std::uint32_t c,
                                    const std::int32_t blocks[27], CellNeighborhood& out) {
    const cell_key::CellCoords cc = cell_key::mortonCoords(g.cellKey[c]);
    out.count = 0;
    for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
                const std::int64_t x = std::int64_t(cc.x) + dx, y = std::int64_t(cc.y) + dy,
                                   z = std::int64_t(cc.z) + dz;
                if (x < 0 || y < 0 || z < 0 || x >= cell_key::kCellsPerAxis ||
                    y >= cell_key::kCellsPerAxis || z >= cell_key::kCellsPerAxis)
                    continue;
                // Which of the 27 blocks, and where in it.
                const int bx = int(x >> 2) - int(cc.x >> 2), by = int(y >> 2) - int(cc.y >> 2),
                          bz = int(z >> 2) - int(cc.z >> 2);
                const std::uint32_t sub = static_cast<std::uint32_t>(
                    cell_key::mortonKey({std::uint32_t(x & 3), std::uint32_t(y & 3),
                                         std::uint32_t(z & 3)}));
                const std::int32_t n = g.cellInBlock(blocks[offsetCode(bx, by, bz)], sub);
                if (n < 0) continue;
                // Insert in increasing cell order (at most 27 entries).
                std::uint32_t k = out.count++;
                while (k > 0 && out.cell[k - 1] > std::uint32_t(n)) {
                    out.cell[k] = out.cell[k - 1];
                    out.offset[k] = out.offset[k - 1];
                    --k;
                }
                out.cell[k] = std::uint32_t(n);
                out.offset[k] = static_cast<std::uint8_t>(offsetCode(dx, dy, dz));
            }
}

// Calls visit(first, last) for the particle ranges of the cells of `nb` (the
// neighbourhood of the cell holding p) that come within the kernel radius of
// p, in increasing index order, ranges of consecutive cells merged. Cells
// farther than h from p hold no neighbour and are skipped. Distances are
// measured in cell units from the same float arithmetic that chose p's cell,
// with a margin that grows with the coordinates (a float's rounding error
// grows with its magnitude): nothing closer than h is ever dropped, far from
// the frame's origin the stencil just culls less. Always inlined: in portable
// builds the caller is a SIMD kernel compiled for a wider instruction set.
template <class Visit>
PBF_HD PBF_ALWAYS_INLINE void forEachStencilRange(const SparseGridView& g,
                                                  const CellNeighborhood& nb, std::uint32_t cell,
                                                  const Vec3& p, Visit&& visit) {
    // Where p lies in its cell along each axis, in [0, 1] (clamped: for
    // points beyond the key's range this underestimates the distance to the
    // neighbours, so nothing closer than h is dropped).
    const cell_key::CellCoords c = cell_key::mortonCoords(g.cellKey[cell]);
    const std::uint32_t cc[3] = {c.x, c.y, c.z};
    float lower[3], upper[3];
    float magnitude = 0.0f;  // the largest |coordinate| involved, in cells
    for (int a = 0; a < 3; ++a) {
        const float f = (p[a] - g.frame.origin[a]) * g.frame.inverseCell - float(cc[a]);
        lower[a] = f < 0.0f ? 0.0f : (f > 1.0f ? 1.0f : f);
        upper[a] = 1.0f - lower[a];
        const float o = g.frame.origin[a];
        const float m = ((p[a] < 0.0f ? -p[a] : p[a]) + (o < 0.0f ? -o : o)) * g.frame.inverseCell;
        magnitude = m > magnitude ? m : magnitude;
    }
    // A few float roundings of the largest magnitude (2^-20 of it), and 1e-4.
    const float margin = 1e-4f + magnitude * (1.0f / 1048576.0f);
    const float reach2 = (1.0f + margin) * (1.0f + margin);
    std::uint32_t first = 0, last = 0;  // the range being merged
    for (std::uint32_t k = 0; k < nb.count; ++k) {
        const int code = nb.offset[k];
        const int d[3] = {code % 3 - 1, (code / 3) % 3 - 1, code / 9 - 1};
        float r2 = 0.0f;
        for (int a = 0; a < 3; ++a) {
            const float gap = d[a] < 0 ? lower[a] : (d[a] > 0 ? upper[a] : 0.0f);
            r2 += gap * gap;
        }
        if (r2 >= reach2) continue;
        const std::uint32_t begin = g.cellStart[nb.cell[k]], end = g.cellStart[nb.cell[k] + 1];
        if (begin == last && last != first) {
            last = end;
            continue;
        }
        if (last != first) visit(first, last);
        first = begin;
        last = end;
    }
    if (last != first) visit(first, last);
}

// The occupied cells and blocks of keys sorted increasingly (host side).
struct SparseCells {
    std::vector<std::uint64_t> cellKey;
    std::vector<std::uint32_t> cellStart;
    std::vector<std::uint64_t> blockKey;
    std::vector<std::uint32_t> blockFirstCell;
    std::vector<std::uint64_t> blockMask;

    // Rebuilt from n sorted keys (no allocation once the sizes settle).
    void build(const std::uint64_t* sortedKeys, std::size_t n);
    SparseGridView view(const cell_key::CellFrame& frame) const {
        return {frame,
                cellKey.data(),
                cellStart.data(),
                static_cast<std::uint32_t>(cellKey.size()),
                blockKey.data(),
                blockFirstCell.data(),
                blockMask.data(),
                static_cast<std::uint32_t>(blockKey.size())};
    }
    std::size_t memoryBytes() const {
        return 8 * (cellKey.capacity() + blockKey.capacity() + blockMask.capacity()) +
               4 * (cellStart.capacity() + blockFirstCell.capacity());
    }
};

inline void SparseCells::build(const std::uint64_t* sortedKeys, std::size_t n) {
    cellKey.clear();
    cellStart.clear();
    blockKey.clear();
    blockFirstCell.clear();
    blockMask.clear();
    for (std::size_t i = 0; i < n; ++i) {
        const std::uint64_t key = sortedKeys[i];
        if (!cellKey.empty() && cellKey.back() == key) continue;
        const std::uint64_t block = key >> kBlockShift;
        if (blockKey.empty() || blockKey.back() != block) {
            blockKey.push_back(block);
            blockFirstCell.push_back(static_cast<std::uint32_t>(cellKey.size()));
            blockMask.push_back(0);
        }
        blockMask.back() |= std::uint64_t{1} << (key & 63u);
        cellKey.push_back(key);
        cellStart.push_back(static_cast<std::uint32_t>(i));
    }
    cellStart.push_back(static_cast<std::uint32_t>(n));
}

}  // namespace pbf::grid
