// The reference backend's neighbour search (private header): particles
// sorted by the uniform grid cell (edge = the search radius) that holds
// them, and for each particle a scan of its own and the 26 adjacent cells.
// Chosen to be obviously correct, not fast: no reordering of the particles,
// no SIMD, one binary search per cell.
//
// Two particles closer than the radius lie in the same or in adjacent cells.
// Positions outside the grid are clamped to its border cells, which keeps
// that true (clamping never moves two points apart in cell coordinates).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "pbf/core/vec3.hpp"

namespace pbf::reference {

class NeighborGrid {
  public:
    // A grid over `domain` with cells of edge `radius`.
    NeighborGrid(const Aabb& domain, float radius);

    // Lists, for every particle i, the particles j != i with
    // |x_i - x_j|^2 < radius^2 (float arithmetic, as written in build()).
    void build(std::span<const Vec3> positions);

    // Neighbours of particle i, in the order the stencil visits them.
    std::span<const std::uint32_t> neighbors(std::size_t i) const {
        return {indices_.data() + offsets_[i], offsets_[i + 1] - offsets_[i]};
    }
    std::size_t totalNeighborCount() const { return indices_.size(); }
    std::size_t memoryBytes() const;

  private:
    struct CellEntry {
        std::uint64_t cell;
        std::uint32_t particle;
    };
    // Cell coordinates of p, clamped to the grid.
    void cellOf(const Vec3& p, std::int64_t cell[3]) const;
    std::uint64_t key(std::int64_t cx, std::int64_t cy, std::int64_t cz) const;

    Aabb domain_;
    float radius_;
    std::int64_t dims_[3];
    std::vector<CellEntry> sorted_;     // (cell, particle), by cell then particle
    std::vector<std::size_t> offsets_;  // particle i's list is [offsets_[i], offsets_[i + 1])
    std::vector<std::uint32_t> indices_;
};

}  // namespace pbf::reference
