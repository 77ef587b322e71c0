#include "pbf/neighbor_search.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>

#include "parallel.hpp"
#include "simd.hpp"

namespace pbf {
namespace {

std::uint32_t cellsAlong(float extent, float cell) {
    return static_cast<std::uint32_t>(std::max(1.0f, std::ceil(extent / cell)));
}

namespace hn = simd::hn;

// Particle i and the distance test against it, set up once per particle.
struct RowTest {
    const float* px;
    const float* py;
    const float* pz;
    std::size_t n;
    std::uint32_t i;
    float xi, yi, zi, r2max;
    simd::FloatVec vxi, vyi, vzi, vr2max;
    simd::IntVec self;

    HWY_INLINE RowTest(const Float3Array& positions, std::size_t particle, float radius)
        : px(positions.x.data()),
          py(positions.y.data()),
          pz(positions.z.data()),
          n(positions.size()),
          i(static_cast<std::uint32_t>(particle)),
          xi(px[particle]),
          yi(py[particle]),
          zi(pz[particle]),
          r2max(radius * radius) {
        const simd::FloatTag d;
        vxi = hn::Set(d, xi);
        vyi = hn::Set(d, yi);
        vzi = hn::Set(d, zi);
        vr2max = hn::Set(d, r2max);
        self = hn::Set(simd::IntTag{}, static_cast<std::int32_t>(i));
    }
};

// Appends to `out` the particles of [first, last) closer than h to i (not
// i); returns their number. Wide lists store 32-bit indices, compact ones
// 16-bit offsets from `base`. `out` has room for last - first entries plus
// one vector.
template <bool Wide>
HWY_INLINE std::size_t collectRow(const RowTest& t, std::uint32_t base, std::uint32_t first,
                                  std::uint32_t last, std::uint16_t* out) {
    const simd::FloatTag d;
    const simd::IntTag di;
    const hn::Rebind<std::uint16_t, simd::IntTag> d16;
    const simd::IntVec vbase = hn::Set(di, static_cast<std::int32_t>(base));
    const std::size_t lanes = hn::Lanes(d);
    std::size_t found = 0;
    std::uint32_t j = first;
    // Full vectors while they stay inside the arrays (lanes past `last` are
    // masked off; reading them is harmless).
    for (; j < last && j + lanes <= t.n; j += static_cast<std::uint32_t>(lanes)) {
        const simd::FloatVec dx = hn::Sub(t.vxi, hn::LoadU(d, t.px + j));
        const simd::FloatVec dy = hn::Sub(t.vyi, hn::LoadU(d, t.py + j));
        const simd::FloatVec dz = hn::Sub(t.vzi, hn::LoadU(d, t.pz + j));
        const simd::FloatVec r2 = hn::MulAdd(dx, dx, hn::MulAdd(dy, dy, hn::Mul(dz, dz)));
        const simd::FloatMask close = hn::And(hn::FirstN(d, last - j), hn::Lt(r2, t.vr2max));
        const simd::IntVec index = hn::Iota(di, static_cast<std::int32_t>(j));
        const auto take = hn::AndNot(hn::Eq(index, t.self), hn::RebindMask(di, close));
        const simd::IntVec taken = hn::Compress(index, take);
        if constexpr (Wide) {
            hn::StoreU(taken, di, reinterpret_cast<std::int32_t*>(out + 2 * found));
        } else {
            hn::StoreU(hn::DemoteTo(d16, hn::Sub(taken, vbase)), d16, out + found);
        }
        found += hn::CountTrue(di, take);
    }
    // The array's last few particles, one at a time, branch-free.
    for (; j < last; ++j) {
        const float dx = t.xi - t.px[j], dy = t.yi - t.py[j], dz = t.zi - t.pz[j];
        if constexpr (Wide) {
            std::memcpy(out + 2 * found, &j, sizeof j);
        } else {
            out[found] = static_cast<std::uint16_t>(j - base);
        }
        found += static_cast<std::size_t>((dx * dx + dy * dy + dz * dz < t.r2max) & (j != t.i));
    }
    return found;
}

}  // namespace

NeighborSearch::NeighborSearch(const Aabb& domain, float radius, std::size_t maxCells,
                               std::uint32_t compactSpan)
    : domain_(domain),
      radius_(radius),
      inverseCell_(1.0f / radius),
      compactSpan_(std::min<std::uint32_t>(compactSpan, 65536)) {
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
    perm.resize(n);
    detail::parallelFor(n, [&](std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i)
            cellOfParticle_[i] = cellIndexOf(positions.get(i));
    });
    // Stable counting sort: particles keep their relative order inside a
    // cell, so the result is the same whatever the thread count. The starts
    // serve as the cursors, then move back one cell (no second table).
    std::fill(cellStart_.begin(), cellStart_.end(), 0u);
    for (std::size_t i = 0; i < n; ++i) ++cellStart_[cellOfParticle_[i] + 1];
    for (std::size_t c = 0; c < cellCount_; ++c) cellStart_[c + 1] += cellStart_[c];
    for (std::size_t i = 0; i < n; ++i)
        perm[cellStart_[cellOfParticle_[i]]++] = static_cast<std::uint32_t>(i);
    std::copy_backward(cellStart_.begin(), cellStart_.end() - 1, cellStart_.end());
    cellStart_[0] = 0;
}

template <class Visit>
void NeighborSearch::forEachStencilRange(const Vec3& p, Visit&& visit) const {
    const std::uint32_t cx = cellCoord(p.x, domain_.min.x, nx_);
    const std::uint32_t cy = cellCoord(p.y, domain_.min.y, ny_);
    const std::uint32_t cz = cellCoord(p.z, domain_.min.z, nz_);
    // Distances from p to the lower and upper faces of its cell, clamped into
    // the cell (for points outside the grid this underestimates the distance
    // to the rows, so nothing closer than h is dropped).
    const float cell = radius_;
    auto faces = [cell](float value, float origin, std::uint32_t c, float& lower, float& upper) {
        lower = std::clamp(value - origin - float(c) * cell, 0.0f, cell);
        upper = cell - lower;
    };
    float lx, ux, ly, uy, lz, uz;
    faces(p.x, domain_.min.x, cx, lx, ux);
    faces(p.y, domain_.min.y, cy, ly, uy);
    faces(p.z, domain_.min.z, cz, lz, uz);
    // Rows (or their end cells) farther than h from p hold no neighbour: skip
    // them. The margin keeps rounding from dropping a particle at r ~ h.
    const float reach2 = radius_ * radius_ * (1.0f + 1e-4f);
    const std::uint32_t z0 = cz > 0 ? cz - 1 : 0;
    const std::uint32_t z1 = std::min(cz + 1, nz_ - 1);
    const std::uint32_t y0 = cy > 0 ? cy - 1 : 0;
    const std::uint32_t y1 = std::min(cy + 1, ny_ - 1);
    for (std::uint32_t z = z0; z <= z1; ++z) {
        const float dz = z < cz ? lz : (z > cz ? uz : 0.0f);
        for (std::uint32_t y = y0; y <= y1; ++y) {
            const float dy = y < cy ? ly : (y > cy ? uy : 0.0f);
            const float left = reach2 - dy * dy - dz * dz;  // squared x reach left over
            if (left <= 0.0f) continue;
            const std::uint32_t x0 = cx > 0 && lx * lx < left ? cx - 1 : cx;
            const std::uint32_t x1 = cx + 1 < nx_ && ux * ux < left ? cx + 1 : cx;
            const std::size_t row = std::size_t{nx_} * (y + std::size_t{ny_} * z);
            visit(cellStart_[row + x0], cellStart_[row + x1 + 1]);
        }
    }
}

void NeighborSearch::buildNeighborLists(const Float3Array& positions) {
    static_assert(kListBlockSize == detail::kBlockSize, "lists are built per parallelFor block");
    const std::size_t n = positions.size();
    listStart_.resize(n);
    listCount_.resize(n);
    blockCount_ = (n + kListBlockSize - 1) / kListBlockSize;
    if (blocks_.size() < blockCount_) blocks_.resize(blockCount_);
    blockNeighbors_.assign(blockCount_, 0);

    // Each block of particles writes its lists into its own buffer, kept
    // between steps; the lists stay there (no copy into one array). When the
    // indices a block can reach span at most 65536 (most blocks: sorted
    // particles are near their neighbours in memory) the lists store 16-bit
    // offsets from the lowest, halving their memory. Each row is a contiguous candidate range,
    // tested a SIMD vector at a time; the indices of the candidates closer than h are compressed
    // into the list in index order.
    detail::parallelFor(n, [&](std::size_t begin, std::size_t end) {
        ListBlock& block = blocks_[begin / kListBlockSize];
        // The stencils of the block's cells (sorted: from the first
        // particle's to the last one's) lie within one z-slab and row of
        // them, so its lists index [lowest, highest).
        const std::size_t reach = std::size_t{nx_} * ny_ + nx_ + 1;
        const std::size_t firstCell = cellIndexOf(positions.get(begin));
        const std::size_t lastCell = cellIndexOf(positions.get(end - 1));
        const std::uint32_t lowest = cellStart_[firstCell > reach ? firstCell - reach : 0];
        const std::uint32_t highest = cellStart_[std::min(lastCell + reach + 1, cellCount_)];
        block.wide = highest - lowest > compactSpan_;
        block.base = block.wide ? 0 : lowest;
        const std::size_t units = block.wide ? 2 : 1;  // 16-bit units per entry
        std::size_t used = 0;                          // entries
        for (std::size_t i = begin; i < end; ++i) {
            std::uint32_t rowFirst[9], rowLast[9];
            int rows = 0;
            std::size_t candidates = 0;
            forEachStencilRange(positions.get(i), [&](std::uint32_t first, std::uint32_t last) {
                rowFirst[rows] = first;
                rowLast[rows++] = last;
                candidates += last - first;
            });
            // Room for every candidate and a vector's overhang (grows rarely,
            // amortised; reserve first: resize alone may double the capacity).
            const std::size_t needed = units * (used + candidates + simd::kMaxLanes);
            if (block.entries.size() < needed) {
                const std::size_t grown = needed + needed / 16 + 1024;
                block.entries.reserve(grown);
                block.entries.resize(grown);
            }
            const RowTest test(positions, i, radius_);
            const std::size_t before = used;
            std::uint16_t* out = block.entries.data();
            for (int r = 0; r < rows; ++r)
                used +=
                    block.wide
                        ? collectRow<true>(test, 0, rowFirst[r], rowLast[r], out + 2 * used)
                        : collectRow<false>(test, block.base, rowFirst[r], rowLast[r], out + used);
            listStart_[i] = static_cast<std::uint32_t>(units * before);
            listCount_[i] = static_cast<std::uint32_t>(used - before);
        }
        // Slack past the last list: SIMD loops read it as list entries, so
        // keep it valid (0: the block's base index).
        std::fill_n(block.entries.begin() + static_cast<std::ptrdiff_t>(units * used),
                    units * simd::kMaxLanes, std::uint16_t{0});
        blockNeighbors_[begin / kListBlockSize] = used;
    });
    totalNeighbors_ = 0;
    for (std::size_t b = 0; b < blockCount_; ++b) totalNeighbors_ += blockNeighbors_[b];
}

std::size_t NeighborSearch::compactBlockCount() const {
    std::size_t compact = 0;
    for (std::size_t b = 0; b < blockCount_; ++b) compact += blocks_[b].wide ? 0 : 1;
    return compact;
}

std::size_t NeighborSearch::memoryBytes() const {
    std::size_t blockBytes = 0;
    for (const ListBlock& block : blocks_)
        blockBytes += sizeof(std::uint16_t) * block.entries.capacity();
    return blockBytes +
           sizeof(std::uint32_t) * (cellOfParticle_.capacity() + cellStart_.capacity() +
                                    listStart_.capacity() + listCount_.capacity()) +
           sizeof(std::size_t) * blockNeighbors_.capacity();
}

}  // namespace pbf
