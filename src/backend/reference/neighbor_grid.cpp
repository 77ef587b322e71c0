#include "backend/reference/neighbor_grid.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace pbf::reference {

NeighborGrid::NeighborGrid(const Aabb& domain, float radius) : domain_(domain), radius_(radius) {
    if (!(radius > 0.0f)) throw std::invalid_argument("NeighborGrid: radius must be positive");
    const Vec3 extent = domain.extent();
    for (int axis = 0; axis < 3; ++axis)
        dims_[axis] = std::max<std::int64_t>(
            1, static_cast<std::int64_t>(std::ceil(double(extent[axis]) / double(radius))));
}

void NeighborGrid::cellOf(const Vec3& p, std::int64_t cell[3]) const {
    for (int axis = 0; axis < 3; ++axis) {
        const double t = std::floor(double(p[axis] - domain_.min[axis]) / double(radius_));
        // Clamp in double first: NaN and far-away points land in a border cell.
        const double clamped = std::clamp(t, 0.0, double(dims_[axis] - 1));
        cell[axis] = std::isnan(t) ? 0 : static_cast<std::int64_t>(clamped);
    }
}

std::uint64_t NeighborGrid::key(std::int64_t cx, std::int64_t cy, std::int64_t cz) const {
    return static_cast<std::uint64_t>(cx + dims_[0] * (cy + dims_[1] * cz));
}

void NeighborGrid::build(std::span<const Vec3> positions) {
    const std::size_t n = positions.size();
    sorted_.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        std::int64_t cell[3];
        cellOf(positions[i], cell);
        sorted_[i] = {key(cell[0], cell[1], cell[2]), static_cast<std::uint32_t>(i)};
    }
    std::sort(sorted_.begin(), sorted_.end(), [](const CellEntry& a, const CellEntry& b) {
        return a.cell != b.cell ? a.cell < b.cell : a.particle < b.particle;
    });

    const float r2max = radius_ * radius_;
    offsets_.assign(n + 1, 0);
    indices_.clear();
    for (std::size_t i = 0; i < n; ++i) {
        const Vec3 xi = positions[i];
        std::int64_t c[3];
        cellOf(xi, c);
        for (std::int64_t z = std::max<std::int64_t>(0, c[2] - 1);
             z <= std::min(dims_[2] - 1, c[2] + 1); ++z)
            for (std::int64_t y = std::max<std::int64_t>(0, c[1] - 1);
                 y <= std::min(dims_[1] - 1, c[1] + 1); ++y)
                for (std::int64_t x = std::max<std::int64_t>(0, c[0] - 1);
                     x <= std::min(dims_[0] - 1, c[0] + 1); ++x) {
                    const std::uint64_t k = key(x, y, z);
                    auto first = std::lower_bound(
                        sorted_.begin(), sorted_.end(), k,
                        [](const CellEntry& e, std::uint64_t value) { return e.cell < value; });
                    for (; first != sorted_.end() && first->cell == k; ++first) {
                        const std::uint32_t j = first->particle;
                        if (j != i && lengthSquared(xi - positions[j]) < r2max)
                            indices_.push_back(j);
                    }
                }
        offsets_[i + 1] = indices_.size();
    }
}

std::size_t NeighborGrid::memoryBytes() const {
    return sizeof(CellEntry) * sorted_.capacity() + sizeof(std::size_t) * offsets_.capacity() +
           sizeof(std::uint32_t) * indices_.capacity();
}

}  // namespace pbf::reference
