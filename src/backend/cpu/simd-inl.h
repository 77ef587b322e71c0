// SIMD helpers for the neighbour loops, on Google Highway, compiled once per
// instruction set target (Highway's foreach_target: each file that includes
// this header after <hwy/foreach_target.h> gets a copy of these helpers in
// pbf::simd::N_<TARGET>). Native builds compile only the host's target
// (HWY_COMPILE_ONLY_STATIC); portable builds compile every x86 target and
// pick the best one at run time. Private header.
//
// Why not `#pragma omp simd`: GCC 12 vectorised those loops but reduced the
// 16 lanes of each accumulator one by one, in order, and ran a scalar
// remainder loop for the last count % 16 neighbours; with ~28 neighbours per
// particle most of the time went to those two scalar parts (perf annotate).
// Here every neighbour is handled in full vectors (the tail masked) and each
// accumulator is reduced with one tree sum.
//
// Determinism: the lanes and their order of reduction depend only on the
// neighbour count and the target, never on the thread that runs the
// particle.

// Per-target include guard (Highway's convention).
#if defined(PBF_SIMD_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef PBF_SIMD_INL_H_
#undef PBF_SIMD_INL_H_
#else
#define PBF_SIMD_INL_H_
#endif

#include <hwy/highway.h>

#include <cstddef>
#include <cstdint>
#include <cstring>

#include "backend/cpu/simd.hpp"

HWY_BEFORE_NAMESPACE();
namespace pbf::simd::HWY_NAMESPACE {

namespace hn = hwy::HWY_NAMESPACE;

using FloatTag = hn::ScalableTag<float>;
using IntTag = hn::RebindToSigned<FloatTag>;
using FloatVec = hn::Vec<FloatTag>;
using IntVec = hn::Vec<IntTag>;
using FloatMask = hn::Mask<FloatTag>;

// Sum of all lanes (a fixed tree for a given target).
HWY_INLINE float sumOfLanes(FloatVec v) {
    return hn::GetLane(hn::SumOfLanes(FloatTag{}, v));
}

// 1 / sqrt(x) to about 23 bits: the hardware estimate refined by one Newton
// step, much cheaper than a square root and a division. x must be > 0.
HWY_INLINE FloatVec reciprocalSqrt(FloatVec x) {
    const FloatTag d;
    const FloatVec y = hn::ApproximateReciprocalSqrt(x);
    // y (1.5 - 0.5 x y^2)
    const FloatVec halfXY2 = hn::Mul(hn::Mul(hn::Set(d, 0.5f), x), hn::Mul(y, y));
    return hn::Mul(y, hn::Sub(hn::Set(d, 1.5f), halfXY2));
}

// Entry k of a neighbour list: 32-bit indices in wide lists, 16-bit
// offsets from the block's base index in compact ones (the caller offsets
// the records it indexes by that base).
template <bool Wide>
HWY_INLINE std::uint32_t listEntry(const std::uint16_t* list, std::size_t k) {
    if constexpr (Wide) {
        std::uint32_t value;
        std::memcpy(&value, list + 2 * k, sizeof value);
        return value;
    } else {
        return list[k];
    }
}

// The list entries list[0 .. lanes) as 32-bit indices (see listEntry).
template <bool Wide>
HWY_INLINE IntVec listIndices(const std::uint16_t* list) {
    const IntTag di;
    if constexpr (Wide) {
        return hn::LoadU(di, reinterpret_cast<const std::int32_t*>(list));
    } else {
        const hn::Rebind<std::uint16_t, IntTag> d16;
        const hn::RebindToUnsigned<IntTag> du;
        return hn::BitCast(di, hn::PromoteTo(du, hn::LoadU(d16, list)));
    }
}

// Four floats per element (x, y, z, w of 16-byte aligned records) of the
// list entries list[0 .. lanes), as four vectors. All lanes' entries must be
// readable and valid (lists keep zeroed slack at their end; lanes past the
// list's end are masked by the caller). On AVX-512 each record is one
// 16-byte load and a 4x4 transpose puts the lanes in order: a quarter of the
// loads of four gathers, which dominated the neighbour loops (the solve ran
// 2x faster with contiguous loads in their place). Elsewhere: four gathers.
struct Gathered4 {
    FloatVec x, y, z, w;
};

// `Stride`: floats from one element's record to the next (4 for the packed
// points; a longer record has its first four floats read,
// 16-byte loads without alignment).
template <bool Wide, std::size_t Stride = 4>
HWY_INLINE Gathered4 gather4(const float* records, const std::uint16_t* list) {
    static_assert(Stride >= 4);
    const FloatTag d;
#if HWY_ARCH_X86 && HWY_TARGET <= HWY_AVX3
    static_assert(hn::MaxLanes(FloatTag{}) == 16);
    (void)d;
    auto record = [&](int lane) {
        const float* at = records + Stride * static_cast<std::size_t>(listEntry<Wide>(list, lane));
        if constexpr (Stride % 4 == 0)
            return _mm_load_ps(at);
        else
            return _mm_loadu_ps(at);
    };
    // q[m] holds the records of lanes m, 4 + m, 8 + m, 12 + m (one per 128-bit block).
    __m512 q[4];
    for (int m = 0; m < 4; ++m) {
        q[m] = _mm512_castps128_ps512(record(m));
        q[m] = _mm512_insertf32x4(q[m], record(4 + m), 1);
        q[m] = _mm512_insertf32x4(q[m], record(8 + m), 2);
        q[m] = _mm512_insertf32x4(q[m], record(12 + m), 3);
    }
    const __m512 xy01 = _mm512_unpacklo_ps(q[0], q[1]);  // x0 x1 y0 y1 per block
    const __m512 zw01 = _mm512_unpackhi_ps(q[0], q[1]);
    const __m512 xy23 = _mm512_unpacklo_ps(q[2], q[3]);
    const __m512 zw23 = _mm512_unpackhi_ps(q[2], q[3]);
    return {FloatVec{_mm512_shuffle_ps(xy01, xy23, 0x44)},
            FloatVec{_mm512_shuffle_ps(xy01, xy23, 0xEE)},
            FloatVec{_mm512_shuffle_ps(zw01, zw23, 0x44)},
            FloatVec{_mm512_shuffle_ps(zw01, zw23, 0xEE)}};
#else
    const IntVec index = listIndices<Wide>(list);
    IntVec at;
    if constexpr (Stride == 4)
        at = hn::ShiftLeft<2>(index);
    else
        at = hn::Mul(index, hn::Set(IntTag{}, std::int32_t(Stride)));
    return {hn::GatherIndex(d, records, at), hn::GatherIndex(d, records + 1, at),
            hn::GatherIndex(d, records + 2, at), hn::GatherIndex(d, records + 3, at)};
#endif
}

}  // namespace pbf::simd::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#endif  // per-target include guard
