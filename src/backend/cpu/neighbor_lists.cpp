// The SIMD kernel of the neighbour-list build, compiled once per
// instruction set target by Highway's foreach_target (see simd-inl.h).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "backend/cpu/neighbor_lists.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include <cstddef>
#include <cstdint>
#include <cstring>

#include "backend/cpu/neighbor_lists.hpp"
#include "backend/cpu/simd-inl.h"
#include "backend/cpu/simd.hpp"

HWY_BEFORE_NAMESPACE();
namespace pbf::grid::HWY_NAMESPACE {

namespace hn = hwy::HWY_NAMESPACE;
using namespace pbf::simd::HWY_NAMESPACE;

// Particle i and the distance test against it, set up once per particle.
struct RowTest {
    const float* px;
    const float* py;
    const float* pz;
    std::size_t n;
    std::uint32_t i;
    float xi, yi, zi, r2max;
    FloatVec vxi, vyi, vzi, vr2max;
    IntVec self;
    IntVec laneIndex;  // 0, 1, 2, ...: built once (Iota goes through memory on some targets)

    HWY_INLINE RowTest(const ListJob& job, std::size_t particle)
        : px(job.px),
          py(job.py),
          pz(job.pz),
          n(job.n),
          i(static_cast<std::uint32_t>(particle)),
          xi(px[particle]),
          yi(py[particle]),
          zi(pz[particle]),
          r2max(job.grid.frame.cell * job.grid.frame.cell) {
        const FloatTag d;
        vxi = hn::Set(d, xi);
        vyi = hn::Set(d, yi);
        vzi = hn::Set(d, zi);
        vr2max = hn::Set(d, r2max);
        self = hn::Set(IntTag{}, static_cast<std::int32_t>(i));
        laneIndex = hn::Iota(IntTag{}, 0);
    }
};

// Appends to `out` the particles of [first, last) closer than h to i (not
// i); returns their number. Wide lists store 32-bit indices, compact ones
// 16-bit offsets from `base`. `out` has room for last - first entries plus
// one vector.
template <bool Wide>
HWY_INLINE std::size_t collectRow(const RowTest& t, std::uint32_t base, std::uint32_t first,
                                  std::uint32_t last, std::uint16_t* out) {
    const FloatTag d;
    const IntTag di;
    const hn::Rebind<std::uint16_t, IntTag> d16;
    const IntVec vbase = hn::Set(di, static_cast<std::int32_t>(base));
    const std::size_t lanes = hn::Lanes(d);
    std::size_t found = 0;
    std::uint32_t j = first;
    // Full vectors while they stay inside the arrays (lanes past `last` are
    // masked off; reading them is harmless).
    for (; j < last && j + lanes <= t.n; j += static_cast<std::uint32_t>(lanes)) {
        const FloatVec dx = hn::Sub(t.vxi, hn::LoadU(d, t.px + j));
        const FloatVec dy = hn::Sub(t.vyi, hn::LoadU(d, t.py + j));
        const FloatVec dz = hn::Sub(t.vzi, hn::LoadU(d, t.pz + j));
        const FloatVec r2 = hn::MulAdd(dx, dx, hn::MulAdd(dy, dy, hn::Mul(dz, dz)));
        const FloatMask close = hn::And(hn::FirstN(d, last - j), hn::Lt(r2, t.vr2max));
        const IntVec index = hn::Add(hn::Set(di, static_cast<std::int32_t>(j)), t.laneIndex);
        const auto take = hn::AndNot(hn::Eq(index, t.self), hn::RebindMask(di, close));
        const IntVec taken = hn::Compress(index, take);
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

std::size_t CollectBlockLists(const ListJob& job, std::size_t begin, std::size_t end,
                              std::size_t& used) {
    const std::size_t units = job.wide ? 2 : 1;  // 16-bit units per entry
    std::uint32_t cell = job.firstCell;
    for (std::size_t i = begin; i < end; ++i) {
        while (job.grid.cellStart[cell + 1] <= i) ++cell;
        std::uint32_t rangeFirst[27], rangeLast[27];
        int ranges = 0;
        std::size_t candidates = 0;
        forEachStencilRange(job.grid, job.cells[cell - job.firstCell],
                            {job.px[i], job.py[i], job.pz[i]},
                            [&](std::uint32_t first, std::uint32_t last) {
                                rangeFirst[ranges] = first;
                                rangeLast[ranges++] = last;
                                candidates += last - first;
                            });
        // Room for every candidate and a vector's overhang.
        if (units * (used + candidates + simd::kMaxLanes) > job.capacity) return i;
        const RowTest test(job, i);
        const std::size_t before = used;
        for (int r = 0; r < ranges; ++r)
            used += job.wide ? collectRow<true>(test, 0, rangeFirst[r], rangeLast[r],
                                                job.entries + 2 * used)
                             : collectRow<false>(test, job.base, rangeFirst[r], rangeLast[r],
                                                 job.entries + used);
        job.listStart[i] = static_cast<std::uint32_t>(units * before);
        job.listCount[i] = static_cast<std::uint32_t>(used - before);
    }
    return end;
}

}  // namespace pbf::grid::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace pbf::grid {

HWY_EXPORT(CollectBlockLists);

std::size_t collectBlockLists(const ListJob& job, std::size_t begin, std::size_t end,
                              std::size_t& used) {
    return HWY_DYNAMIC_DISPATCH(CollectBlockLists)(job, begin, end, used);
}

}  // namespace pbf::grid
#endif  // HWY_ONCE
