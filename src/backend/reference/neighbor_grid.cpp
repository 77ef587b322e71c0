#include "backend/reference/neighbor_grid.hpp"

#include <algorithm>
#include <stdexcept>

namespace pbf::reference {

NeighborGrid::NeighborGrid(const Aabb& domain, float radius) {
    if (!(radius > 0.0f)) throw std::invalid_argument("NeighborGrid: radius must be positive");
    if (!cell_key::domainFrame(domain, radius, frame_))
        throw std::invalid_argument("NeighborGrid: the domain is wider than the cell key's range");
}

void NeighborGrid::build(std::span<const Vec3> positions) {
    const std::size_t n = positions.size();
    sorted_.resize(n);
    for (std::size_t i = 0; i < n; ++i)
        sorted_[i] = {frame_.keyOf(positions[i]), static_cast<std::uint32_t>(i)};
    std::sort(sorted_.begin(), sorted_.end(), [](const CellEntry& a, const CellEntry& b) {
        return a.cell != b.cell ? a.cell < b.cell : a.particle < b.particle;
    });

    const float r2max = frame_.cell * frame_.cell;
    const std::int64_t top = frame_.maxCoordinate;
    offsets_.assign(n + 1, 0);
    indices_.clear();
    for (std::size_t i = 0; i < n; ++i) {
        const Vec3 xi = positions[i];
        const cell_key::CellCoords c = frame_.coords(xi);
        const std::int64_t cx = c.x, cy = c.y, cz = c.z;
        for (std::int64_t z = std::max<std::int64_t>(0, cz - 1); z <= std::min(top, cz + 1); ++z)
            for (std::int64_t y = std::max<std::int64_t>(0, cy - 1); y <= std::min(top, cy + 1);
                 ++y)
                for (std::int64_t x = std::max<std::int64_t>(0, cx - 1);
                     x <= std::min(top, cx + 1); ++x) {
                    const std::uint64_t k = cell_key::cellKey(
                        {std::uint32_t(x), std::uint32_t(y), std::uint32_t(z)});
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
