#include "pbf/neighbor_search.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "parallel.hpp"
#include "simd.hpp"

namespace pbf {
namespace {

std::uint32_t cellsAlong(float extent, float cell) {
    return static_cast<std::uint32_t>(std::max(1.0f, std::ceil(extent / cell)));
}

}  // namespace

NeighborSearch::NeighborSearch(const Aabb& domain, float radius, std::size_t maxCells)
    : domain_(domain), radius_(radius), inverseCell_(1.0f / radius) {
    if (!(radius > 0.0f)) throw std::invalid_argument("neighbour search radius must be positive");
    const Vec3 e = domain.extent();
    const double cells = std::ceil(double(e.x) / radius) * std::ceil(double(e.y) / radius) *
                         std::ceil(double(e.z) / radius);
    if (!(cells <= double(maxCells)))
        throw std::invalid_argument(
            "the domain is " + std::to_string(static_cast<long long>(cells)) +
            " grid cells of the kernel radius, more than the limit of " + std::to_string(maxCells) +
            "; use a smaller domain or larger particles");
    nx_ = cellsAlong(e.x, radius);
    ny_ = cellsAlong(e.y, radius);
    nz_ = cellsAlong(e.z, radius);
    cellCount_ = std::size_t{nx_} * ny_ * nz_;
    cellStart_.assign(cellCount_ + 1, 0);
    cellCursor_.assign(cellCount_ + 1, 0);
}

std::uint32_t NeighborSearch::cellCoord(float value, float origin, std::uint32_t count) const {
    const float c = std::floor((value - origin) * inverseCell_);
    // Clamp (also catches NaN via the comparisons' false branch).
    if (!(c > 0.0f)) return 0;
    if (c >= float(count - 1)) return count - 1;
    return static_cast<std::uint32_t>(c);
}

std::uint32_t NeighborSearch::cellIndexOf(const Vec3& p) const {
    const std::uint32_t cx = cellCoord(p.x, domain_.min.x, nx_);
    const std::uint32_t cy = cellCoord(p.y, domain_.min.y, ny_);
    const std::uint32_t cz = cellCoord(p.z, domain_.min.z, nz_);
    return cx + nx_ * (cy + ny_ * cz);
}

void NeighborSearch::sortByCell(const Float3Array& positions, std::vector<std::uint32_t>& perm) {
    const std::size_t n = positions.size();
    cellOfParticle_.resize(n);
    sortedCell_.resize(n);
    perm.resize(n);
    detail::parallelFor(n, [&](std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i)
            cellOfParticle_[i] = cellIndexOf(positions.get(i));
    });
    // Stable counting sort: particles keep their relative order inside a
    // cell, so the result is the same whatever the thread count.
    std::fill(cellStart_.begin(), cellStart_.end(), 0u);
    for (std::size_t i = 0; i < n; ++i) ++cellStart_[cellOfParticle_[i] + 1];
    for (std::size_t c = 0; c < cellCount_; ++c) cellStart_[c + 1] += cellStart_[c];
    std::copy(cellStart_.begin(), cellStart_.end(), cellCursor_.begin());
    for (std::size_t i = 0; i < n; ++i) {
        const std::uint32_t c = cellOfParticle_[i];
        const std::uint32_t slot = cellCursor_[c]++;
        perm[slot] = static_cast<std::uint32_t>(i);
        sortedCell_[slot] = c;
    }
}

template <class Visit>
void NeighborSearch::forEachStencilRange(std::uint32_t cx, std::uint32_t cy, std::uint32_t cz,
                                         Visit&& visit) const {
    const std::uint32_t x0 = cx > 0 ? cx - 1 : 0;
    const std::uint32_t x1 = std::min(cx + 1, nx_ - 1);
    const std::uint32_t z0 = cz > 0 ? cz - 1 : 0;
    const std::uint32_t z1 = std::min(cz + 1, nz_ - 1);
    const std::uint32_t y0 = cy > 0 ? cy - 1 : 0;
    const std::uint32_t y1 = std::min(cy + 1, ny_ - 1);
    for (std::uint32_t z = z0; z <= z1; ++z) {
        for (std::uint32_t y = y0; y <= y1; ++y) {
            const std::size_t row = std::size_t{nx_} * (y + std::size_t{ny_} * z);
            visit(cellStart_[row + x0], cellStart_[row + x1 + 1]);
        }
    }
}

void NeighborSearch::buildNeighborLists(const Float3Array& positions) {
    const std::size_t n = positions.size();
    counts_.resize(n);
    offsets_.resize(n + 1);
    const float r2max = radius_ * radius_;
    const float* px = positions.x.data();
    const float* py = positions.y.data();
    const float* pz = positions.z.data();

    // One distance pass: each block of particles appends its lists to its
    // own buffer (kept between steps), then the buffers are copied into the
    // CSR array at offsets from a prefix sum over the counts. Each stencil row
    // is tested branch-free (an index is always written, the cursor advances
    // only for a neighbour): about one candidate in eight is a neighbour, so
    // a branch per candidate would mispredict often.
    const std::size_t blocks = (n + detail::kBlockSize - 1) / detail::kBlockSize;
    if (blockLists_.size() < blocks) blockLists_.resize(blocks);
    detail::parallelFor(n, [&](std::size_t begin, std::size_t end) {
        std::vector<std::uint32_t>& list = blockLists_[begin / detail::kBlockSize];
        std::size_t used = 0;
        for (std::size_t i = begin; i < end; ++i) {
            const std::uint32_t c = sortedCell_[i];
            const std::uint32_t cx = c % nx_;
            const std::uint32_t cy = (c / nx_) % ny_;
            const std::uint32_t cz = c / (nx_ * ny_);
            const float xi = px[i], yi = py[i], zi = pz[i];
            const std::size_t before = used;
            forEachStencilRange(cx, cy, cz, [&](std::uint32_t first, std::uint32_t last) {
                // Room for every candidate of the row (grows rarely, amortised).
                if (list.size() < used + (last - first))
                    list.resize(2 * (used + (last - first)) + 1024);
                std::uint32_t* out = list.data() + used;
                std::size_t found = 0;
                for (std::uint32_t j = first; j < last; ++j) {
                    const float dx = xi - px[j], dy = yi - py[j], dz = zi - pz[j];
                    out[found] = j;
                    found +=
                        static_cast<std::size_t>((dx * dx + dy * dy + dz * dz < r2max) & (j != i));
                }
                used += found;
            });
            counts_[i] = static_cast<std::uint32_t>(used - before);
        }
    });
    offsets_[0] = 0;
    for (std::size_t i = 0; i < n; ++i) offsets_[i + 1] = offsets_[i] + counts_[i];
    // Grows only when the total exceeds every earlier step's (amortised).
    // Slack past the end: SIMD loads of a list's last batch may over-read.
    if (indices_.size() < offsets_[n] + simd::kMaxLanes)
        indices_.resize(offsets_[n] + offsets_[n] / 4 + simd::kMaxLanes);
    // ... and read past a list's end as particle indices: keep them valid.
    std::fill_n(indices_.begin() + static_cast<std::ptrdiff_t>(offsets_[n]), simd::kMaxLanes, 0u);
    detail::parallelFor(n, [&](std::size_t begin, std::size_t end) {
        const std::vector<std::uint32_t>& list = blockLists_[begin / detail::kBlockSize];
        const std::size_t used = offsets_[end] - offsets_[begin];
        std::copy(list.begin(), list.begin() + static_cast<std::ptrdiff_t>(used),
                  indices_.begin() + static_cast<std::ptrdiff_t>(offsets_[begin]));
    });
}

std::size_t NeighborSearch::memoryBytes() const {
    std::size_t blockBytes = 0;
    for (const auto& list : blockLists_) blockBytes += sizeof(std::uint32_t) * list.capacity();
    return blockBytes +
           sizeof(std::uint32_t) *
               (cellOfParticle_.capacity() + cellStart_.capacity() + cellCursor_.capacity() +
                sortedCell_.capacity() + counts_.capacity() + indices_.capacity()) +
           sizeof(std::size_t) * offsets_.capacity();
}

}  // namespace pbf
