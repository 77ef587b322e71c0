// The sparse grid: particles sorted by cell key (core/cell_key.hpp), the
// occupied cells as a sorted list with start offsets, and the stencil walk
// around a particle (private header, PBF_HD: the CPU search, the GPU kernels
// and their tests share it).
//
// Nothing here is sized by the domain. A cell's 26 neighbours are found by
// their rows: a row (64 cells along x whose first x is a multiple of 64, at
// one y and z) is one contiguous key range, key >> 6 is its own code, and a
// 64-bit mask says which of its cells hold particles. A cell's neighbourhood
// lies in the 27 rows around its own (the 9 rows at y and z plus and minus
// one, and the rows before and after those along x), found once per row by
// binary search over the occupied rows; each neighbour cell is then one
// popcount away. The CPU search does this once per occupied cell while it
// builds the lists, the GPU once per particle.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/cell_key.hpp"
#include "pbf/core/config.hpp"
#include "pbf/core/vec3.hpp"

namespace pbf::grid {

// The sparse grid's blocks are the key's rows of 64 cells along x.
inline constexpr int kBlockShift = cell_key::kRowBits;  // key bits of the cells inside a row
static_assert(kBlockShift == 6, "a block's occupancy is one 64-bit mask");

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
    const std::uint64_t* blockKey;        // occupied rows (cell key >> 6), increasing
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
};

// Offset code of a neighbour: (dx + 1) + 3 (dy + 1) + 9 (dz + 1); 13 is the cell itself.
PBF_HD inline int offsetCode(int dx, int dy, int dz) {
    return (dx + 1) + 3 * (dy + 1) + 9 * (dz + 1);
}

// A block's coordinates (x in rows, y and z in cells) and back.
PBF_HD inline cell_key::CellCoords blockCoords(std::uint64_t blockKey) {
    cell_key::CellCoords c = cell_key::cellCoords(blockKey << kBlockShift);
    c.x >>= kBlockShift;
    return c;
}
PBF_HD inline std::uint64_t blockKeyOf(cell_key::CellCoords block) {
    return cell_key::cellKey({block.x << kBlockShift, block.y, block.z}) >> kBlockShift;
}

// The 27 blocks around block b (b included, code 13), -1 where none is
// occupied. The blocks before (after) along x are looked up only when b's
// first (last) cell is occupied: only a cell at the row's end reaches into
// them (cellNeighborhood), and most rows have none there, which saves 18 of
// the 26 binary searches.
PBF_HD inline void blockNeighborhood(const SparseGridView& g, std::uint32_t b, std::int32_t out[27]) {
    const cell_key::CellCoords c = blockCoords(g.blockKey[b]);
    constexpr std::int64_t kRows = cell_key::kCellsPerAxis >> kBlockShift;
    constexpr std::int64_t kCells = cell_key::kCellsPerAxis;
    const std::uint64_t mask = g.blockMask[b];
    const bool reachesBefore = (mask & 1u) != 0, reachesAfter = (mask >> 63) != 0;
    for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
                const std::int64_t x = std::int64_t(c.x) + dx, y = std::int64_t(c.y) + dy,
                                   z = std::int64_t(c.z) + dz;
                const bool reached = dx == 0 || (dx < 0 ? reachesBefore : reachesAfter);
                const bool inside = reached && x >= 0 && y >= 0 && z >= 0 && x < kRows &&
                                    y < kCells && z < kCells;
                out[offsetCode(dx, dy, dz)] =
                    (dx == 0 && dy == 0 && dz == 0)
                        ? static_cast<std::int32_t>(b)
                        : (inside ? g.findBlock(blockKeyOf({std::uint32_t(x), std::uint32_t(y),
                                                            std::uint32_t(z)}))
                                  : -1);
            }
}

// An occupied cell's occupied neighbours (itself included) as runs, in
// increasing index order: the order their particles lie in memory. A run is
// what one row of the key holds of the cell's neighbourhood: up to three
// consecutive cells, at x - 1, x, x + 1, whose particles are one range,
// [lo, a) at x - 1, [a, b) at x, [b, hi) at x + 1 (any part may be
// empty). Rows at y and z plus and minus one give nine runs; a cell at a
// row's end adds the rows before or after along x (a run of one cell each).
struct CellNeighborhood {
    cell_key::CellCoords centre;  // the cell's own coordinates
    std::uint32_t count;          // runs
    std::uint32_t lo[18], a[18], b[18], hi[18];
    std::uint8_t row[18];  // the run's row: (dy + 1) + 3 (dz + 1)
};

PBF_HD inline int lowestBit(std::uint64_t v) {
#if defined(__CUDA_ARCH__)
    return __ffsll(static_cast<long long>(v)) - 1;
#else
    return __builtin_ctzll(v);
#endif
}

// The neighbourhood of cell c, given the neighbourhood of its block
// (blockNeighborhood of cellKey[c] >> 6's index). The cell's neighbours are
// the cells at x - 1, x, x + 1 of the 9 rows at y and z plus and minus one
// (three bits of each row's mask), and where the cell ends its row, the
// first or last cell of the rows before or after: at most 18 rows, each one
// mask and'ed with the row's occupancy, each one run. Rows in increasing
// index order give the runs in increasing index order, with no per-cell
// search.
PBF_HD inline void cellNeighborhood(const SparseGridView& g, std::uint32_t c,
                                    const std::int32_t blocks[27], CellNeighborhood& out) {
    const std::uint64_t key = g.cellKey[c];
    out.centre = cell_key::cellCoords(key);
    out.count = 0;
    constexpr std::uint32_t kLast = (1u << kBlockShift) - 1u;
    const std::uint32_t p = static_cast<std::uint32_t>(key) & kLast;  // x inside the row
    // The cells the cell reaches in the row before (step 0), its own (1),
    // after (2) along x.
    const std::uint64_t reach[3] = {
        p == 0 ? std::uint64_t{1} << kLast : 0,
        p == 0 ? std::uint64_t{3} : std::uint64_t{7} << (p - 1),  // x + 1 = 64 shifts out
        p == kLast ? std::uint64_t{1} : 0};
    // The touched rows (at most 18), in increasing row index.
    std::int32_t blockIndex[18];
    std::uint64_t wanted[18];
    int blockCode[18];
    int touched = 0;
    for (int code = 0; code < 27; ++code) {
        const std::uint64_t row = reach[code % 3];
        if (row == 0 || blocks[code] < 0) continue;
        const std::uint64_t occupied = row & g.blockMask[blocks[code]];
        if (occupied == 0) continue;
        int k = touched++;
        while (k > 0 && blockIndex[k - 1] > blocks[code]) {
            blockIndex[k] = blockIndex[k - 1];
            wanted[k] = wanted[k - 1];
            blockCode[k] = blockCode[k - 1];
            --k;
        }
        blockIndex[k] = blocks[code];
        wanted[k] = occupied;
        blockCode[k] = code;
    }
    for (int b = 0; b < touched; ++b) {
        const std::uint64_t mask = g.blockMask[blockIndex[b]];
        const std::uint64_t bits = wanted[b];
        const int code = blockCode[b];
        // The run's cells are consecutive in index: the first at the
        // popcount below the lowest wanted bit, one more per wanted bit.
        const int first = lowestBit(bits);
        const std::uint32_t c0 = g.blockFirstCell[blockIndex[b]] +
                                 std::uint32_t(popcount64(mask & ((std::uint64_t{1} << first) - 1u)));
        const std::uint32_t cells = std::uint32_t(popcount64(bits));
        const std::uint32_t lo = g.cellStart[c0], hi = g.cellStart[c0 + cells];
        // Which parts it has: in its own row, the cell before x when that
        // bit is set, after x likewise; a row before (after) along x holds
        // only the part before (after).
        const int step = code % 3;
        const bool hasBefore = step == 0 || (step == 1 && p > 0 && ((bits >> (p - 1)) & 1u));
        const bool hasAfter = step == 2 || (step == 1 && p < kLast && ((bits >> (p + 1)) & 1u));
        const std::uint32_t k = out.count++;
        out.lo[k] = lo;
        out.hi[k] = hi;
        out.a[k] = step == 2 ? lo : (hasBefore ? g.cellStart[c0 + 1] : lo);
        out.b[k] = step == 0 ? hi : (hasAfter ? g.cellStart[c0 + cells - 1] : hi);
        out.row[k] = static_cast<std::uint8_t>(code / 3);
    }
}

// Calls visit(first, last) for the particle ranges of the cells of `nb` (the
// neighbourhood of the cell holding p) that come within the kernel radius of
// p, in increasing index order, consecutive ranges merged: per run, its row
// when the row comes within reach, trimmed at either end by the cell there
// when that cell does not (the dense grid's walk). Cells farther than h
// from p hold no neighbour and are skipped. Distances are
// measured in cell units from the same float arithmetic that chose p's cell,
// with a margin that grows with the coordinates (a float's rounding error
// grows with its magnitude): nothing closer than h is ever dropped, far from
// the frame's origin the stencil just culls less. Always inlined: in portable
// builds the caller is a SIMD kernel compiled for a wider instruction set.
template <class Visit>
PBF_HD PBF_ALWAYS_INLINE void forEachStencilRange(const SparseGridView& g,
                                                  const CellNeighborhood& nb, const Vec3& p,
                                                  Visit&& visit) {
    // Where p lies in its cell along each axis, in [0, 1] (clamped: for
    // points beyond the key's range this underestimates the distance to the
    // neighbours, so nothing closer than h is dropped).
    const std::uint32_t cc[3] = {nb.centre.x, nb.centre.y, nb.centre.z};
    const Vec3 q = g.frame.keyAxes(p);  // the frame's origin and coordinates are in key axes
    // gap2[a][s]: the squared distance from p to the neighbour cells of step
    // s - 1 along axis a (0 for its own column).
    float gap2[3][3];
    float magnitude = 0.0f;  // the largest |coordinate| involved, in cells
    for (int a = 0; a < 3; ++a) {
        const float f = (q[a] - g.frame.origin[a]) * g.frame.inverseCell - float(cc[a]);
        const float lower = f < 0.0f ? 0.0f : (f > 1.0f ? 1.0f : f);
        const float upper = 1.0f - lower;
        gap2[a][0] = lower * lower;
        gap2[a][1] = 0.0f;
        gap2[a][2] = upper * upper;
        const float o = g.frame.origin[a];
        const float m = ((q[a] < 0.0f ? -q[a] : q[a]) + (o < 0.0f ? -o : o)) * g.frame.inverseCell;
        magnitude = m > magnitude ? m : magnitude;
    }
    // A few float roundings of the largest magnitude (2^-20 of it), and 1e-4.
    const float margin = 1e-4f + magnitude * (1.0f / 1048576.0f);
    const float reach2 = (1.0f + margin) * (1.0f + margin);
    // The reach left along each of the 9 rows (offset sy, sz across them)
    // once the distance across is spent: a row is out of reach when none is
    // left, its cell before (after) p's column when the gap to it exceeds
    // what is left. Constant indices: the compiler keeps them in registers.
    float left[9];
    for (int sz = 0; sz < 3; ++sz)
        for (int sy = 0; sy < 3; ++sy) left[sy + 3 * sz] = reach2 - gap2[1][sy] - gap2[2][sz];
    std::uint32_t first = 0, last = 0;  // the range being merged
    for (std::uint32_t k = 0; k < nb.count; ++k) {
        const float reachLeft = left[nb.row[k]];
        if (!(reachLeft > 0.0f)) continue;  // the row is out of reach
        const std::uint32_t begin = gap2[0][0] < reachLeft ? nb.lo[k] : nb.a[k];
        const std::uint32_t end = gap2[0][2] < reachLeft ? nb.hi[k] : nb.b[k];
        if (begin >= end) continue;
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
