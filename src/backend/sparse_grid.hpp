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
    cell_key::CellCoords centre;  // the cell's own coordinates
    std::uint32_t count;
    std::uint32_t cell[27];
    std::uint32_t begin[27], end[27];  // the particles of each: [begin, end)
    std::uint8_t offset[27];           // offsetCode of each
};


// The cells of a 4x4x4 block whose coordinate along `axis` is in the set
// `coords` (bit v: coordinate v), as a mask over the block's Morton-ordered
// cells (bit axis of the cell's index is the coordinate's low bit, bit
// axis + 3 its high bit); the and of three is a box's mask.
PBF_HD inline std::uint64_t axisMask(int axis, std::uint32_t coords) {
    constexpr std::uint64_t kLowBit[3] = {0xAAAAAAAAAAAAAAAAull, 0xCCCCCCCCCCCCCCCCull,
                                          0xF0F0F0F0F0F0F0F0ull};
    constexpr std::uint64_t kHighBit[3] = {0xFF00FF00FF00FF00ull, 0xFFFF0000FFFF0000ull,
                                           0xFFFFFFFF00000000ull};
    const std::uint64_t low = kLowBit[axis], high = kHighBit[axis];
    std::uint64_t mask = 0;
    if (coords & 1u) mask |= ~low & ~high;
    if (coords & 2u) mask |= low & ~high;
    if (coords & 4u) mask |= ~low & high;
    if (coords & 8u) mask |= low & high;
    return mask;
}

PBF_HD inline int lowestBit(std::uint64_t v) {
#if defined(__CUDA_ARCH__)
    return __ffsll(static_cast<long long>(v)) - 1;
#else
    return __builtin_ctzll(v);
#endif
}

// The neighbourhood of cell c, given the neighbourhood of its block
// (blockNeighborhood of cellKey[c] >> 6's index). Per axis, the cell's
// neighbours lie in its own block's 4 columns (the cell's coordinate there
// plus and minus one, within 0..3), and in the block before or after only
// where the cell sits on that face; so they are the occupied cells of at
// most 8 boxes, one per block, each a mask and'ed with the block's
// occupancy. Blocks in increasing index order and, inside one, cells in
// increasing Morton order give the cells in increasing index order, with no
// sort and no per-cell search.
PBF_HD inline void cellNeighborhood(const SparseGridView& g, std::uint32_t c,
                                    const std::int32_t blocks[27], CellNeighborhood& out) {
    const std::uint64_t key = g.cellKey[c];
    out.centre = cell_key::mortonCoords(key);
    out.count = 0;
    const std::uint32_t own[3] = {cell_key::compactBits(key & 63u),
                                  cell_key::compactBits((key >> 1) & 31u),
                                  cell_key::compactBits((key >> 2) & 15u)};
    // Per axis and block step s - 1: the coordinates (bit set) the cell
    // reaches in that block, and the mask of the cells with them.
    std::uint64_t reach[3][3];
    for (int a = 0; a < 3; ++a) {
        const std::uint32_t p = own[a];
        const std::uint32_t inside = (0x7u << p >> 1) & 0xFu;  // p - 1, p, p + 1 within 0..3
        reach[a][0] = p == 0 ? axisMask(a, 0x8u) : 0;
        reach[a][1] = axisMask(a, inside);
        reach[a][2] = p == 3 ? axisMask(a, 0x1u) : 0;
    }
    // The touched blocks (at most 8), in increasing block index.
    std::int32_t blockIndex[8];
    std::uint64_t wanted[8];
    int blockCode[8];
    int touched = 0;
    for (int sz = 0; sz < 3; ++sz)
        for (int sy = 0; sy < 3; ++sy)
            for (int sx = 0; sx < 3; ++sx) {
                const std::uint64_t box = reach[0][sx] & reach[1][sy] & reach[2][sz];
                const int code = sx + 3 * sy + 9 * sz;
                if (box == 0 || blocks[code] < 0) continue;
                const std::uint64_t occupied = box & g.blockMask[blocks[code]];
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
        const int step[3] = {blockCode[b] % 3 - 1, (blockCode[b] / 3) % 3 - 1, blockCode[b] / 9 - 1};
        for (std::uint64_t bits = wanted[b]; bits != 0; bits &= bits - 1) {
            const int sub = lowestBit(bits);
            const std::uint64_t below = mask & ((std::uint64_t{1} << sub) - 1u);
            const std::uint32_t cell =
                g.blockFirstCell[blockIndex[b]] + std::uint32_t(popcount64(below));
            out.cell[out.count] = cell;
            out.begin[out.count] = g.cellStart[cell];
            out.end[out.count] = g.cellStart[cell + 1];
            const int d[3] = {
                4 * step[0] + int(cell_key::compactBits(std::uint64_t(sub))) - int(own[0]),
                4 * step[1] + int(cell_key::compactBits(std::uint64_t(sub) >> 1)) - int(own[1]),
                4 * step[2] + int(cell_key::compactBits(std::uint64_t(sub) >> 2)) - int(own[2])};
            out.offset[out.count++] = static_cast<std::uint8_t>(offsetCode(d[0], d[1], d[2]));
        }
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
    (void)cell;
    const std::uint32_t cc[3] = {nb.centre.x, nb.centre.y, nb.centre.z};
    // gap2[a][s]: the squared distance from p to the neighbour cells of step
    // s - 1 along axis a (0 for its own column).
    float gap2[3][3];
    float magnitude = 0.0f;  // the largest |coordinate| involved, in cells
    for (int a = 0; a < 3; ++a) {
        const float f = (p[a] - g.frame.origin[a]) * g.frame.inverseCell - float(cc[a]);
        const float lower = f < 0.0f ? 0.0f : (f > 1.0f ? 1.0f : f);
        const float upper = 1.0f - lower;
        gap2[a][0] = lower * lower;
        gap2[a][1] = 0.0f;
        gap2[a][2] = upper * upper;
        const float o = g.frame.origin[a];
        const float m = ((p[a] < 0.0f ? -p[a] : p[a]) + (o < 0.0f ? -o : o)) * g.frame.inverseCell;
        magnitude = m > magnitude ? m : magnitude;
    }
    // A few float roundings of the largest magnitude (2^-20 of it), and 1e-4.
    const float margin = 1e-4f + magnitude * (1.0f / 1048576.0f);
    const float reach2 = (1.0f + margin) * (1.0f + margin);
    // Bit `code` set: the neighbour cell of that offset comes within reach.
    // Branch-free over constant indices (the compiler unrolls it and keeps
    // the gaps in registers): the walk below then tests one bit per cell.
    std::uint32_t within = 0;
    for (int sz = 0; sz < 3; ++sz)
        for (int sy = 0; sy < 3; ++sy)
            for (int sx = 0; sx < 3; ++sx)
                within |= std::uint32_t(gap2[0][sx] + gap2[1][sy] + gap2[2][sz] < reach2)
                          << (sx + 3 * sy + 9 * sz);
    std::uint32_t first = 0, last = 0;  // the range being merged
    for (std::uint32_t k = 0; k < nb.count; ++k) {
        if (!((within >> nb.offset[k]) & 1u)) continue;
        const std::uint32_t begin = nb.begin[k], end = nb.end[k];
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
