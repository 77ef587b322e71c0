// The sorted grid as plain data, and the stencil rows around a point: shared
// by NeighborSearch and its per-target SIMD list kernel (neighbor_lists.cpp).
// Private header.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "pbf/core/config.hpp"
#include "pbf/core/vec3.hpp"

namespace pbf::grid {

// Cells are numbered with the axes ordered by the domain's extent: the
// shortest axis varies fastest (stencil rows run along it and are contiguous
// in memory), the longest slowest. A particle's neighbours then lie within
// one slab of the two shorter axes' cells, the smallest the domain allows:
// that keeps the neighbour passes' reads in cache and the blocks' lists
// compact. (For the dam break, 1.6 x 1.0 x 0.4 m, a slab of the x-major
// order holds a quarter of the cells of the z-major one.)
struct GridView {
    Aabb domain;
    float cell;  // edge of a cell: the kernel radius h
    float inverseCell;
    int axis[3];                     // axis[0] fastest (rows), axis[2] slowest
    std::uint32_t n[3];              // cells along axis[k]
    const std::uint32_t* cellStart;  // particles of cell c: [cellStart[c], cellStart[c + 1])

    // Cell coordinate of `value` along an axis, clamped into the grid (also
    // catches NaN via the comparisons' false branch). For t > 0 truncation
    // is floor, so no libm call in builds without SSE4.1's round.
    PBF_HD std::uint32_t coordinate(float value, float origin, std::uint32_t count) const {
        const float t = (value - origin) * inverseCell;
        if (!(t > 0.0f)) return 0;
        if (t >= float(count - 1)) return count - 1;
        return static_cast<std::uint32_t>(t);
    }
    // Coordinate along axis[k].
    PBF_HD std::uint32_t coordinate(const Vec3& p, int k) const {
        return coordinate(p[axis[k]], domain.min[axis[k]], n[k]);
    }

    PBF_HD std::uint32_t cellIndexOf(const Vec3& p) const {
        return coordinate(p, 0) + n[0] * (coordinate(p, 1) + n[1] * coordinate(p, 2));
    }
};

// The grid over `domain` with cells of edge `cell` (cellStart left null):
// axes from the shortest extent (fastest, rows) to the longest, ties in x,
// y, z order; at least one cell per axis.
inline GridView gridLayout(const Aabb& domain, float cell) {
    GridView g{domain, cell, 1.0f / cell, {0, 1, 2}, {1, 1, 1}, nullptr};
    const Vec3 e = domain.extent();
    std::stable_sort(g.axis, g.axis + 3, [&e](int a, int b) { return e[a] < e[b]; });
    for (int k = 0; k < 3; ++k)
        g.n[k] = static_cast<std::uint32_t>(std::max(1.0f, std::ceil(e[g.axis[k]] / cell)));
    return g;
}

// Calls visit(first, last) for the particle ranges of the rows (along
// axis[0], adjacent in memory) of the 27-cell stencil around p's cell, in
// increasing index order, without the rows and end cells farther than h
// from p. Always inlined: in portable builds the caller is a SIMD kernel
// compiled for a wider instruction set, and GCC would otherwise keep this
// walk (and the kernel's `visit`) as calls. The GPU backend walks the same
// stencil (PBF_HD).
template <class Visit>
PBF_HD PBF_ALWAYS_INLINE void forEachStencilRow(const GridView& g, const Vec3& p, Visit&& visit) {
    const std::uint32_t c0 = g.coordinate(p, 0);
    const std::uint32_t c1 = g.coordinate(p, 1);
    const std::uint32_t c2 = g.coordinate(p, 2);
    // Distances from p to the lower and upper faces of its cell, clamped into
    // the cell (for points outside the grid this underestimates the distance
    // to the rows, so nothing closer than h is dropped).
    const float cell = g.cell;
    auto faces = [&](int k, std::uint32_t c, float& lower, float& upper) {
        const int a = g.axis[k];
        lower = std::clamp(p[a] - g.domain.min[a] - float(c) * cell, 0.0f, cell);
        upper = cell - lower;
    };
    float l0, u0, l1, u1, l2, u2;
    faces(0, c0, l0, u0);
    faces(1, c1, l1, u1);
    faces(2, c2, l2, u2);
    // Rows (or their end cells) farther than h from p hold no neighbour: skip
    // them. The margin keeps rounding from dropping a particle at r ~ h.
    const float reach2 = cell * cell * (1.0f + 1e-4f);
    const std::uint32_t slow0 = c2 > 0 ? c2 - 1 : 0;
    const std::uint32_t slow1 = std::min(c2 + 1, g.n[2] - 1);
    const std::uint32_t mid0 = c1 > 0 ? c1 - 1 : 0;
    const std::uint32_t mid1 = std::min(c1 + 1, g.n[1] - 1);
    for (std::uint32_t s = slow0; s <= slow1; ++s) {
        const float ds = s < c2 ? l2 : (s > c2 ? u2 : 0.0f);
        for (std::uint32_t m = mid0; m <= mid1; ++m) {
            const float dm = m < c1 ? l1 : (m > c1 ? u1 : 0.0f);
            const float left = reach2 - dm * dm - ds * ds;  // squared reach left along the row
            if (left <= 0.0f) continue;
            const std::uint32_t first = c0 > 0 && l0 * l0 < left ? c0 - 1 : c0;
            const std::uint32_t last = c0 + 1 < g.n[0] && u0 * u0 < left ? c0 + 1 : c0;
            const std::size_t row = std::size_t{g.n[0]} * (m + std::size_t{g.n[1]} * s);
            visit(g.cellStart[row + first], g.cellStart[row + last + 1]);
        }
    }
}

// Neighbour lists of one block of particles, to be written by the SIMD
// kernel (neighbor_lists.cpp).
struct ListJob {
    GridView grid;
    const float* px;
    const float* py;
    const float* pz;
    std::size_t n;  // particles
    bool wide;      // 32-bit indices; else 16-bit offsets from `base`
    std::uint32_t base;
    std::uint16_t* entries;  // the block's buffer
    std::size_t capacity;    // its size, in 16-bit units
    std::uint32_t* listStart;
    std::uint32_t* listCount;
};

// Writes the lists of particles [begin, end) after the `used` entries
// already in the buffer, updating `used`. Stops at the first particle whose
// candidates might not fit and returns it (end when all are done): the
// caller grows the buffer and calls again from there.
std::size_t collectBlockLists(const ListJob& job, std::size_t begin, std::size_t end,
                              std::size_t& used);

}  // namespace pbf::grid
