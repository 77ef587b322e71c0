// Particles sorted by cubic cell, for fixed-radius neighbour queries that
// visit neighbours in the same order whatever the thread count (private
// header of pbf_surface).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <span>
#include <stdexcept>
#include <vector>

#include "core/cell_key.hpp"
#include "pbf/core/vec3.hpp"

namespace pbf::surface::detail {

class SortedCells {
  public:
    // `cell` > 0: the query radius (a query looks at the 27 cells around it).
    SortedCells(std::span<const Vec3> points, double cell) : points_(points), inverse_(1.0 / cell) {
        keys_.resize(points.size());
        order_.resize(points.size());
        for (std::size_t i = 0; i < points.size(); ++i) keys_[i] = key(cellOf(points[i]));
        std::iota(order_.begin(), order_.end(), 0u);
        // Sorted by (cell, index): the visiting order is a property of the
        // input alone.
        std::sort(order_.begin(), order_.end(), [&](std::uint32_t a, std::uint32_t b) {
            return keys_[a] != keys_[b] ? keys_[a] < keys_[b] : a < b;
        });
        std::vector<std::uint64_t> sorted(points.size());
        for (std::size_t k = 0; k < order_.size(); ++k) sorted[k] = keys_[order_[k]];
        keys_ = std::move(sorted);
    }

    // visit(j) for every point j in the 27 cells around p, in a fixed order.
    template <class Visit>
    void forEachNear(Vec3 p, Visit&& visit) const {
        const Cell c = cellOf(p);
        for (int dz = -1; dz <= 1; ++dz)
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const std::uint64_t k = key({c.x + dx, c.y + dy, c.z + dz});
                    const auto range = std::equal_range(keys_.begin(), keys_.end(), k);
                    for (auto it = range.first; it != range.second; ++it)
                        visit(order_[std::size_t(it - keys_.begin())]);
                }
    }

  private:
    struct Cell {
        std::int64_t x, y, z;
    };
    static constexpr std::int64_t kBias = std::int64_t(1) << 20;  // 21 bits per axis

    Cell cellOf(Vec3 p) const {
        const auto axis = [&](float v) {
            const double c = std::floor(double(v) * inverse_);
            // 2^20 cells either way: kilometres at any particle size pbf
            // meshes; beyond that the key would wrap.
            if (!(std::abs(c) < double(kBias - 2)))
                throw std::invalid_argument(
                    "particle position out of range for meshing: " + std::to_string(v) + " m");
            return std::int64_t(c);
        };
        return {axis(p.x), axis(p.y), axis(p.z)};
    }
    // The cell key every neighbour search shares, of the cell's
    // coordinates shifted to be non-negative.
    static std::uint64_t key(Cell c) {
        return cell_key::cellKey({std::uint32_t(c.x + kBias), std::uint32_t(c.y + kBias),
                                    std::uint32_t(c.z + kBias)});
    }

    std::span<const Vec3> points_;
    double inverse_;
    std::vector<std::uint64_t> keys_;   // sorted
    std::vector<std::uint32_t> order_;  // point index of each sorted key
};

}  // namespace pbf::surface::detail
