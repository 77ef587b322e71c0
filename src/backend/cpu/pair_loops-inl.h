// The neighbour-batch loops shared by the SIMD passes (neighbor_passes.cpp,
// surface_tension_pass.cpp): a batch of one particle's neighbours as SIMD
// lanes (geometry, masks, the kernels' shapes), two particles' batches
// interleaved, and ranges split at the neighbour lists' blocks. Compiled
// once per instruction set target like simd-inl.h (include it first).
// Private header.

// Per-target include guard (Highway's convention).
#if defined(PBF_PAIR_LOOPS_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef PBF_PAIR_LOOPS_INL_H_
#undef PBF_PAIR_LOOPS_INL_H_
#else
#define PBF_PAIR_LOOPS_INL_H_
#endif

#include <hwy/highway.h>

#include <algorithm>
#include <cstddef>

#include "backend/cpu/neighbor_search.hpp"
#include "backend/cpu/simd-inl.h"
#include "backend/cpu/solver.hpp"

HWY_BEFORE_NAMESPACE();
namespace pbf::simd::HWY_NAMESPACE {

namespace hn = hwy::HWY_NAMESPACE;

// Per-lane geometry of a batch of neighbours j of particle i.
struct PairBatch {
    FloatVec dx, dy, dz;  // x_i - x_j
    FloatVec w;           // the fourth float of j's packed record
    FloatVec r2;
    FloatMask inside;  // 0 < r < h and a real list entry
    FloatVec inverseR;
};

struct PairConstants {
    FloatVec h, h2, tiny;
};

HWY_INLINE PairConstants pairConstants(float h, float h2) {
    const FloatTag d;
    return {hn::Set(d, h), hn::Set(d, h2), hn::Set(d, 1e-30f)};
}

// `records` are the packed points offset by the list's base index.
template <bool Wide>
HWY_INLINE PairBatch loadPairs(const PairConstants& k, const PackedPoint* records, FloatVec xi,
                               FloatVec yi, FloatVec zi, const NeighborList& list,
                               std::size_t first) {
    const FloatTag d;
    PairBatch b;
    const FloatMask valid = hn::FirstN(d, list.count - first);
    const Gathered4 xj = gather4<Wide>(&records[0].x, list.entries + (Wide ? 2 : 1) * first);
    b.dx = hn::Sub(xi, xj.x);
    b.dy = hn::Sub(yi, xj.y);
    b.dz = hn::Sub(zi, xj.z);
    b.w = xj.w;
    b.r2 = hn::MulAdd(b.dx, b.dx, hn::MulAdd(b.dy, b.dy, hn::Mul(b.dz, b.dz)));
    // Neighbours are closer than h by construction, but x* moved since the
    // lists were built: keep the kernels' support exact.
    b.inside = hn::And(valid, hn::And(hn::Lt(b.r2, k.h2), hn::Gt(b.r2, hn::Zero(d))));
    b.inverseR = reciprocalSqrt(hn::Max(b.r2, k.tiny));
    return b;
}

// (h^2 - r^2)^3, zero outside the support: poly6 / its coefficient.
HWY_INLINE FloatVec poly6Shape(const PairConstants& k, const PairBatch& b) {
    const FloatVec d2 = hn::Sub(k.h2, b.r2);
    return hn::IfThenElseZero(b.inside, hn::Mul(hn::Mul(d2, d2), d2));
}

// (h - r)^2 / r, zero outside the support: |grad spiky| / (r coefficient).
// grad_i W_ij = spiky coefficient * this * (x_i - x_j).
HWY_INLINE FloatVec spikyShapeOverR(const PairConstants& k, const PairBatch& b, FloatVec& squared) {
    const FloatVec dd = hn::Sub(k.h, hn::Mul(b.r2, b.inverseR));
    squared = hn::IfThenElseZero(b.inside, hn::Mul(dd, dd));
    return hn::Mul(squared, b.inverseR);
}

// Runs the neighbour batches of particles i and i + 1 interleaved: one
// particle's batches form a long dependency chain (loads, transpose, kernels,
// accumulation, tree sums), and two independent chains in one loop keep the
// core busier (density pass ~7 %, correction ~3 % faster). Each particle's arithmetic is the
// same as alone, so the pairing cannot change results.
template <class Particle, class Pass>
HWY_INLINE void forEachParticleInterleaved(const Pass& pass, std::size_t begin, std::size_t end) {
    const std::size_t lanes = hn::Lanes(FloatTag{});
    std::size_t i = begin;
    for (; i + 1 < end; i += 2) {
        Particle a(pass, i), b(pass, i + 1);
        const std::size_t longest = std::max(a.list.size(), b.list.size());
        for (std::size_t first = 0; first < longest; first += lanes) {
            if (first < a.list.size()) a.addBatch(pass, first);
            if (first < b.list.size()) b.addBatch(pass, first);
        }
        a.finish(pass, i);
        b.finish(pass, i + 1);
    }
    if (i < end) {
        Particle a(pass, i);
        for (std::size_t first = 0; first < a.list.size(); first += lanes) a.addBatch(pass, first);
        a.finish(pass, i);
    }
}

// Calls fn(begin, end, first list) for the parts of [begin, end) that lie
// in one neighbour-list block each: a block's lists share one base index and
// one width, and a stage's range need not match the blocks.
template <class Fn>
HWY_INLINE void forEachListBlock(const NeighborSearch& search, std::size_t begin, std::size_t end,
                                 const Fn& fn) {
    constexpr std::size_t kBlock = NeighborSearch::kListBlockSize;
    while (begin < end) {
        const std::size_t blockEnd = std::min(end, (begin / kBlock + 1) * kBlock);
        fn(begin, blockEnd, search.neighbors(begin));
        begin = blockEnd;
    }
}

}  // namespace pbf::simd::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#endif  // per-target include guard
