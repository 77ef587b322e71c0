// The cell key: one 64-bit code of a cubic cell's integer coordinates
// (private header, PBF_HD). Every neighbour search in pbf sorts by it: the
// CPU and GPU solvers, the reference backend, the MPI layer and the surface
// code. Only occupied cells are stored anywhere, so memory and time follow
// the particles, not the domain.
//
// The key is a space-filling curve over bricks with rows inside them:
// bricks of 64 x 32 x 32 cells (x, y, z) in Morton's order (the bricks'
// coordinates' bits interleaved), and inside a brick the cells in rows, x
// fastest, then z, then y. These are the key's axes; a frame maps the
// world's onto them (CellFrame::axis; domainFrame puts the domain's
// shortest side along the rows and its longest slowest). A particle's 26 neighbour cells are then 9
// runs of 3 cells contiguous in memory, and the rows the solver's passes read move through memory
// as steadily as a dense grid's (Morton's and Hilbert's orders of single cells scatter them far
// apart and defeat the hardware's prefetch: 20-27 % slower passes at 1M particles,
// bench/cell_key_bench.cpp and docs/performance.md). Three properties the
// searches rely on:
//  * 64 consecutive cells along x whose first x is a multiple of 64 are 64
//    consecutive keys, and key >> 6 is their row's own code: the sparse
//    grid looks cells up by such rows (backend/sparse_grid.hpp);
//  * the key grows with each coordinate separately, so the keys of a box of
//    cells lie between those of its lowest and highest corners (the
//    distributed split tests whole neighbourhoods with two keys);
//  * a brick is one contiguous key range, and Morton's order keeps
//    neighbouring bricks close, so ranges of keys are compact pieces of
//    space (what the distributed split hands each rank).
// Morton's and Hilbert's codes of single cells are here for the measurement
// that chose this layout.
//
// Coordinates have 21 bits each (2,097,152 cells a side: 42 km at a 2 cm
// kernel radius); keys use all 64 bits, and ~0 is never a key.
#pragma once

#include <cmath>
#include <cstdint>

#include "pbf/core/config.hpp"
#include "pbf/core/vec3.hpp"

namespace pbf::cell_key {

inline constexpr int kBitsPerAxis = 21;
inline constexpr std::uint32_t kCellsPerAxis = std::uint32_t{1} << kBitsPerAxis;

// The 21 low bits of v spread to every third bit (bit k to bit 3k).
PBF_HD constexpr std::uint64_t spreadBits(std::uint32_t v) {
    std::uint64_t x = v & 0x1fffffu;
    x = (x | x << 32) & 0x1f00000000ffffull;
    x = (x | x << 16) & 0x1f0000ff0000ffull;
    x = (x | x << 8) & 0x100f00f00f00f00full;
    x = (x | x << 4) & 0x10c30c30c30c30c3ull;
    x = (x | x << 2) & 0x1249249249249249ull;
    return x;
}

// Inverse of spreadBits: every third bit of v (from bit 0) gathered.
PBF_HD constexpr std::uint32_t compactBits(std::uint64_t v) {
    std::uint64_t x = v & 0x1249249249249249ull;
    x = (x ^ (x >> 2)) & 0x10c30c30c30c30c3ull;
    x = (x ^ (x >> 4)) & 0x100f00f00f00f00full;
    x = (x ^ (x >> 8)) & 0x1f0000ff0000ffull;
    x = (x ^ (x >> 16)) & 0x1f00000000ffffull;
    x = (x ^ (x >> 32)) & 0x1fffffull;
    return static_cast<std::uint32_t>(x);
}

// Integer cell coordinates, each in [0, kCellsPerAxis).
struct CellCoords {
    std::uint32_t x, y, z;
    friend constexpr bool operator==(const CellCoords&, const CellCoords&) = default;
};

PBF_HD constexpr std::uint64_t mortonKey(CellCoords c) {
    return spreadBits(c.x) | spreadBits(c.y) << 1 | spreadBits(c.z) << 2;
}

PBF_HD constexpr CellCoords mortonCoords(std::uint64_t key) {
    return {compactBits(key), compactBits(key >> 1), compactBits(key >> 2)};
}

// The layout of bricks and rows: bits of x, z and y inside a brick.
inline constexpr int kRowBits = 6;    // 64 cells along x
inline constexpr int kBrickBits = 5;  // 32 cells along y and z
inline constexpr int kInBrickBits = kRowBits + 2 * kBrickBits;

PBF_HD constexpr std::uint64_t cellKey(CellCoords c) {
    constexpr std::uint32_t kRow = (1u << kRowBits) - 1u, kSide = (1u << kBrickBits) - 1u;
    const std::uint64_t brick = mortonKey({c.x >> kRowBits, c.y >> kBrickBits, c.z >> kBrickBits});
    return brick << kInBrickBits | std::uint64_t(c.y & kSide) << (kRowBits + kBrickBits) |
           std::uint64_t(c.z & kSide) << kRowBits | std::uint64_t(c.x & kRow);
}

PBF_HD constexpr CellCoords cellCoords(std::uint64_t key) {
    constexpr std::uint64_t kRow = (1u << kRowBits) - 1u, kSide = (1u << kBrickBits) - 1u;
    const CellCoords brick = mortonCoords(key >> kInBrickBits);
    return {brick.x << kRowBits | std::uint32_t(key & kRow),
            brick.y << kBrickBits | std::uint32_t((key >> (kRowBits + kBrickBits)) & kSide),
            brick.z << kBrickBits | std::uint32_t((key >> kRowBits) & kSide)};
}

// Hilbert's curve by Skilling's transpose ("Programming the Hilbert curve",
// AIP Conf. Proc. 707, 2004): coordinates -> transposed index -> key.
PBF_HD constexpr std::uint64_t hilbertKey(CellCoords c) {
    std::uint32_t X[3] = {c.x, c.y, c.z};
    for (std::uint32_t q = kCellsPerAxis >> 1; q > 1; q >>= 1) {  // inverse undo
        const std::uint32_t p = q - 1;
        for (int i = 0; i < 3; ++i) {
            if (X[i] & q) {
                X[0] ^= p;
            } else {
                const std::uint32_t t = (X[0] ^ X[i]) & p;
                X[0] ^= t;
                X[i] ^= t;
            }
        }
    }
    X[1] ^= X[0];  // Gray encode
    X[2] ^= X[1];
    std::uint32_t t = 0;
    for (std::uint32_t q = kCellsPerAxis >> 1; q > 1; q >>= 1)
        if (X[2] & q) t ^= q - 1;
    for (std::uint32_t& v : X) v ^= t;
    return spreadBits(X[0]) << 2 | spreadBits(X[1]) << 1 | spreadBits(X[2]);
}

PBF_HD constexpr CellCoords hilbertCoords(std::uint64_t key) {
    std::uint32_t X[3] = {compactBits(key >> 2), compactBits(key >> 1), compactBits(key)};
    const std::uint32_t t0 = X[2] >> 1;  // Gray decode
    X[2] ^= X[1];
    X[1] ^= X[0];
    X[0] ^= t0;
    for (std::uint32_t q = 2; q != kCellsPerAxis; q <<= 1) {  // undo excess work
        const std::uint32_t p = q - 1;
        for (int i = 2; i >= 0; --i) {
            if (X[i] & q) {
                X[0] ^= p;
            } else {
                const std::uint32_t t = (X[0] ^ X[i]) & p;
                X[0] ^= t;
                X[i] ^= t;
            }
        }
    }
    return {X[0], X[1], X[2]};
}

// Bits a key of cells with coordinates below `cellsPerAxis` can use: what a
// radix sort of such keys has to look at (the key grows with each
// coordinate, so the highest corner has the largest key).
PBF_HD constexpr int keyBits(std::uint32_t cellsPerAxis) {
    const std::uint32_t top = cellsPerAxis > 0 ? cellsPerAxis - 1 : 0;
    std::uint64_t largest = cellKey({top, top, top});
    int bits = 0;
    while (largest != 0) {
        ++bits;
        largest >>= 1;
    }
    return bits;
}

// Cubic cells of edge `cell` whose coordinate 0 starts at `origin` on every
// axis, coordinates in [0, maxCoordinate]. Positions below the origin or
// beyond the last cell are clamped to the border cells (and NaN to cell 0):
// clamping is monotone and never moves two points apart in cell coordinates,
// so two points closer than a cell edge stay in the same or adjacent cells
// and searches remain exact.
//
// The key's axes are the world's in an order the frame chooses (`axis`):
// key axis k is world axis axis[k]. Every coordinate and position a frame
// hands out or takes (coords, origin, corner, keyAxes) is in key axes.
struct CellFrame {
    Vec3 origin;  // in key axes
    float cell;
    float inverseCell;
    std::uint32_t maxCoordinate;
    std::uint8_t axis[3] = {0, 1, 2};

    // maxCoordinate + 1 a power of two (at most kCellsPerAxis): the keys
    // then use keyBits(maxCoordinate + 1) bits. `origin` in world axes;
    // `axes[k]`: the world axis of key axis k.
    static CellFrame over(const Vec3& origin, float cell,
                          std::uint32_t maxCoordinate = kCellsPerAxis - 1,
                          const std::uint8_t (&axes)[3] = kWorldAxes) {
        CellFrame f{{}, cell, 1.0f / cell, maxCoordinate, {axes[0], axes[1], axes[2]}};
        f.origin = f.keyAxes(origin);
        return f;
    }
    static constexpr std::uint8_t kWorldAxes[3] = {0, 1, 2};

    // A world position in key axes.
    PBF_HD Vec3 keyAxes(const Vec3& p) const { return {p[axis[0]], p[axis[1]], p[axis[2]]}; }

    // Coordinate of `value` along an axis whose cells start at `start`. For
    // t > 0 truncation is floor (no libm call on the device). Branch-free
    // selects (NaN and t <= 0 give 0) and a signed conversion (t < 2^21), so
    // that the loop over all particles vectorises.
    PBF_HD std::uint32_t coordinate(float value, float start) const {
        float t = (value - start) * inverseCell;
        t = t > 0.0f ? t : 0.0f;
        const float top = float(maxCoordinate);  // exact: below 2^21
        t = t < top ? t : top;
        return static_cast<std::uint32_t>(static_cast<std::int32_t>(t));
    }
    // The cell of a position given in key axes (a loop over many particles
    // permutes its arrays once, then calls this: it vectorises).
    PBF_HD CellCoords coordsOfKeyAxes(const Vec3& q) const {
        return {coordinate(q.x, origin.x), coordinate(q.y, origin.y), coordinate(q.z, origin.z)};
    }
    PBF_HD CellCoords coords(const Vec3& p) const { return coordsOfKeyAxes(keyAxes(p)); }
    PBF_HD std::uint64_t keyOf(const Vec3& p) const { return cellKey(coords(p)); }
    // The lowest corner of a cell, in key axes.
    PBF_HD Vec3 corner(CellCoords c) const {
        return {origin.x + float(c.x) * cell, origin.y + float(c.y) * cell,
                origin.z + float(c.z) * cell};
    }
};

// The frame of a simulation domain: cells of edge `cell` from its lowest
// corner, coordinates up to the next power of two above the cells its
// longest side needs (so the keys use as few bits as the domain allows).
// Returns false when the domain is wider than the key holds (2^21 cells a
// side) or its extent is not a positive finite number.
inline bool domainFrame(const Aabb& domain, float cell, CellFrame& frame) {
    const Vec3 e = domain.extent();
    double widest = 0.0;
    for (int a = 0; a < 3; ++a) {
        const double cells = std::ceil(double(e[a]) / double(cell));
        if (!(cells > 0.0) || !(cells <= double(kCellsPerAxis))) return false;
        widest = cells > widest ? cells : widest;
    }
    std::uint32_t span = 1;
    while (double(span) < widest) span <<= 1;
    // The shortest side along the key's rows, the longest slowest (x of the
    // key, then z, then y): a particle's neighbours then lie within the
    // thinnest slab of memory the domain allows, as they did in the dense
    // grid that numbered its cells this way. Ties keep the world's order.
    std::uint8_t axes[3] = {0, 1, 2};
    for (int i = 1; i < 3; ++i)
        for (int k = i; k > 0 && e[axes[k]] < e[axes[k - 1]]; --k) {
            const std::uint8_t t = axes[k];
            axes[k] = axes[k - 1];
            axes[k - 1] = t;
        }
    // Ascending extent: key x (rows) the shortest, key z the middle, key y
    // the longest.
    const std::uint8_t keyOrder[3] = {axes[0], axes[2], axes[1]};
    frame = CellFrame::over(domain.min, cell, span - 1, keyOrder);
    return true;
}

}  // namespace pbf::cell_key
