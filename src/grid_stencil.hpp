// The sorted grid as plain data, and the stencil rows around a point: shared
// by NeighborSearch and its per-target SIMD list kernel (neighbor_lists.cpp).
// Private header.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "pbf/vec3.hpp"

namespace pbf::grid {

struct GridView {
    Aabb domain;
    float cell;  // edge of a cell: the kernel radius h
    float inverseCell;
    std::uint32_t nx, ny, nz;
    const std::uint32_t* cellStart;  // particles of cell c: [cellStart[c], cellStart[c + 1])

    // Cell coordinate of `value` along an axis, clamped into the grid (also
    // catches NaN via the comparisons' false branch). For t > 0 truncation
    // is floor, so no libm call in builds without SSE4.1's round.
    std::uint32_t coordinate(float value, float origin, std::uint32_t count) const {
        const float t = (value - origin) * inverseCell;
        if (!(t > 0.0f)) return 0;
        if (t >= float(count - 1)) return count - 1;
        return static_cast<std::uint32_t>(t);
    }

    std::uint32_t cellIndexOf(const Vec3& p) const {
        return coordinate(p.x, domain.min.x, nx) +
               nx * (coordinate(p.y, domain.min.y, ny) + ny * coordinate(p.z, domain.min.z, nz));
    }
};

// Calls visit(first, last) for the particle ranges of the x-rows of the
// 27-cell stencil around p's cell (cells along x are adjacent in memory), in
// increasing index order, without the rows and end cells farther than h
// from p. Always inlined: in portable builds the caller is a SIMD kernel
// compiled for a wider instruction set, and GCC would otherwise keep this
// walk (and the kernel's `visit`) as calls.
template <class Visit>
[[gnu::always_inline]] inline void forEachStencilRow(const GridView& g, const Vec3& p,
                                                     Visit&& visit) {
    const std::uint32_t cx = g.coordinate(p.x, g.domain.min.x, g.nx);
    const std::uint32_t cy = g.coordinate(p.y, g.domain.min.y, g.ny);
    const std::uint32_t cz = g.coordinate(p.z, g.domain.min.z, g.nz);
    // Distances from p to the lower and upper faces of its cell, clamped into
    // the cell (for points outside the grid this underestimates the distance
    // to the rows, so nothing closer than h is dropped).
    const float cell = g.cell;
    auto faces = [cell](float value, float origin, std::uint32_t c, float& lower, float& upper) {
        lower = std::clamp(value - origin - float(c) * cell, 0.0f, cell);
        upper = cell - lower;
    };
    float lx, ux, ly, uy, lz, uz;
    faces(p.x, g.domain.min.x, cx, lx, ux);
    faces(p.y, g.domain.min.y, cy, ly, uy);
    faces(p.z, g.domain.min.z, cz, lz, uz);
    // Rows (or their end cells) farther than h from p hold no neighbour: skip
    // them. The margin keeps rounding from dropping a particle at r ~ h.
    const float reach2 = cell * cell * (1.0f + 1e-4f);
    const std::uint32_t z0 = cz > 0 ? cz - 1 : 0;
    const std::uint32_t z1 = std::min(cz + 1, g.nz - 1);
    const std::uint32_t y0 = cy > 0 ? cy - 1 : 0;
    const std::uint32_t y1 = std::min(cy + 1, g.ny - 1);
    for (std::uint32_t z = z0; z <= z1; ++z) {
        const float dz = z < cz ? lz : (z > cz ? uz : 0.0f);
        for (std::uint32_t y = y0; y <= y1; ++y) {
            const float dy = y < cy ? ly : (y > cy ? uy : 0.0f);
            const float left = reach2 - dy * dy - dz * dz;  // squared x reach left over
            if (left <= 0.0f) continue;
            const std::uint32_t x0 = cx > 0 && lx * lx < left ? cx - 1 : cx;
            const std::uint32_t x1 = cx + 1 < g.nx && ux * ux < left ? cx + 1 : cx;
            const std::size_t row = std::size_t{g.nx} * (y + std::size_t{g.ny} * z);
            visit(g.cellStart[row + x0], g.cellStart[row + x1 + 1]);
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
