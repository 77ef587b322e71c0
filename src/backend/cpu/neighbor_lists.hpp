// One block's neighbour lists as plain data, for the SIMD kernel that writes
// them (neighbor_lists.cpp; private header of the CPU search).
#pragma once

#include <cstddef>
#include <cstdint>

#include "backend/sparse_grid.hpp"

namespace pbf::grid {

// Neighbour lists of one block of particles, to be written by the SIMD
// kernel (neighbor_lists.cpp).
struct ListJob {
    SparseGridView grid;
    const CellNeighborhood* cells;  // neighbourhoods of the block's cells, from firstCell on
    std::uint32_t firstCell;        // the cell of the block's first particle
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
