// The reference backend's neighbour search (private header): particles
// sorted by the cell key (core/cell_key.hpp; cells of edge = the search
// radius) of the cell that holds them, and for each particle a scan of its
// own and the 26 adjacent cells. Chosen to be obviously correct, not fast:
// no reordering of the particles, no SIMD, one binary search per cell. Only
// particles are stored: the domain's size costs nothing.
//
// Two particles closer than the radius lie in the same or in adjacent cells.
// Positions outside the key's range are clamped to its border cells, which
// keeps that true (clamping never moves two points apart in cell coordinates).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "core/cell_key.hpp"
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
    cell_key::CellFrame frame_;
    std::vector<CellEntry> sorted_;     // (cell, particle), by cell then particle
    std::vector<std::size_t> offsets_;  // particle i's list is [offsets_[i], offsets_[i + 1])
    std::vector<std::uint32_t> indices_;
};

}  // namespace pbf::reference
