// The SIMD passes of the continuum surface stress (equations.hpp,
// "Continuum surface stress"), vector over the neighbours of one particle
// like surface_tension_pass.cpp: first T_i of every particle from
// g_i = sum_j colourGradientTerm (the walls' and solids' share added per
// particle by reference::surfaceStressFromNeighborGradient), then the
// pair force sum_j surfaceStressPairTerm, v += dt a
// (reference::surfaceStressVelocityChange). The pair terms are the
// reference's, lane for lane (spikyGradientFactor in pair_loops-inl.h: the
// exact 1/r, not the estimate, so that the stage test's bound, which counts
// the sums' order, holds as derived); only the order of the sums differs,
// and it depends on the neighbour count and the target alone, not on the
// thread. docs/performance.md ("The SIMD passes of the stress") gives the
// cost (a substep with surface tension: 1.15-1.27 times one without, 1.7
// times with the scalar passes these replaced).
// Compiled once per instruction set target like neighbor_passes.cpp.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "backend/cpu/surface_stress_pass.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include <cstddef>

#include "backend/cpu/simd-inl.h"
// After simd-inl.h: the neighbour-batch helpers (per target, like it).
#include "backend/cpu/pair_loops-inl.h"
#include "backend/cpu/solver_stages.hpp"
#include "backend/reference/neighbor_sums.hpp"

HWY_BEFORE_NAMESPACE();
namespace pbf::stages::HWY_NAMESPACE {

namespace hn = hwy::HWY_NAMESPACE;
using namespace pbf::simd::HWY_NAMESPACE;

struct SurfaceStressPass {
    const SolverConstants& c;
    const SolidSet* solids;
    float dt;
    const NeighborSearch& search;
    const PackedPoint* predicted;        // x*
    const PackedPoint* neighborRecords;  // predicted + the block's list base
    const Sym3* stress;                  // T (the force pass)
    const Sym3* neighborStress;          // stress + the block's list base
    Sym3* stressOut;                     // T (the stress pass)
    Float3Array* velocity;               // v (the force pass)
    PairConstants k;
    FloatVec gradientCoefficient;  // the spiky kernel's
    FloatVec volume;               // V = m / rho0, as colourGradientTerm rounds it
};

// g_i: the lanes sum colourGradientTerm's (grad W_ij) V, per component as
// the reference rounds it.
template <bool Wide>
struct StressParticle {
    FloatVec xi, yi, zi;
    NeighborList list;
    FloatVec gx, gy, gz;

    HWY_INLINE StressParticle(const SurfaceStressPass& p, std::size_t i)
        : list(p.search.neighbors(i)) {
        const FloatTag d;
        const PackedPoint& x = p.predicted[i];
        xi = hn::Set(d, x.x);
        yi = hn::Set(d, x.y);
        zi = hn::Set(d, x.z);
        gx = gy = gz = hn::Zero(d);
    }

    HWY_INLINE void addBatch(const SurfaceStressPass& p, std::size_t first) {
        const PairBatch b = loadPairs<Wide>(p.k, p.neighborRecords, xi, yi, zi, list, first);
        const FloatVec f = spikyGradientFactor(p.k.h, p.gradientCoefficient, b);
        gx = hn::Add(gx, hn::Mul(hn::Mul(b.dx, f), p.volume));
        gy = hn::Add(gy, hn::Mul(hn::Mul(b.dy, f), p.volume));
        gz = hn::Add(gz, hn::Mul(hn::Mul(b.dz, f), p.volume));
    }

    HWY_INLINE void finish(const SurfaceStressPass& p, std::size_t i) const {
        const PackedPoint& x = p.predicted[i];
        p.stressOut[i] = reference::surfaceStressFromNeighborGradient(
            p.c, p.solids, Vec3{x.x, x.y, x.z},
            Vec3{sumOfLanes(gx), sumOfLanes(gy), sumOfLanes(gz)});
    }
};

// T_j of the list entries list[0 .. lanes) from the Sym3 records (six
// floats each), offset by the block's base like the positions, read as
// gather4 reads the packed points: on AVX-512 floats 0-3 and 2-5 of each
// record by one 16-byte load each and a transpose, no gathers (six gathers
// were most of this pass: perf, docs/performance.md); elsewhere floats
// 0-3 by gather4's gathers and the last two by two more.
struct GatheredStress {
    FloatVec xx, yy, zz, xy, xz, yz;
};

template <bool Wide>
HWY_INLINE GatheredStress gatherStress(const Sym3* records, const std::uint16_t* list) {
    static_assert(sizeof(Sym3) == 6 * sizeof(float));
    const float* base = &records[0].xx;
    const Gathered4 first = gather4<Wide, 6>(base, list);
#if HWY_ARCH_X86 && HWY_TARGET <= HWY_AVX3
    const Gathered4 last = gather4<Wide, 6>(base + 2, list);  // zz, xy, xz, yz
    return {first.x, first.y, first.z, first.w, last.z, last.w};
#else
    const FloatTag d;
    const IntVec at = hn::Mul(listIndices<Wide>(list), hn::Set(IntTag{}, 6));
    return {first.x,
            first.y,
            first.z,
            first.w,
            hn::GatherIndex(d, base + 4, at),
            hn::GatherIndex(d, base + 5, at)};
#endif
}

// sum_j (T_i + T_j) grad W_ij: surfaceStressPairTerm lane for lane (Sym3's
// sum, then its product with the gradient as Sym3::operator* orders it).
template <bool Wide>
struct ForceParticle {
    FloatVec xi, yi, zi;
    GatheredStress ti;
    NeighborList list;
    FloatVec sx, sy, sz;

    HWY_INLINE ForceParticle(const SurfaceStressPass& p, std::size_t i)
        : list(p.search.neighbors(i)) {
        const FloatTag d;
        const PackedPoint& x = p.predicted[i];
        xi = hn::Set(d, x.x);
        yi = hn::Set(d, x.y);
        zi = hn::Set(d, x.z);
        const Sym3& t = p.stress[i];
        ti = {hn::Set(d, t.xx), hn::Set(d, t.yy), hn::Set(d, t.zz),
              hn::Set(d, t.xy), hn::Set(d, t.xz), hn::Set(d, t.yz)};
        sx = sy = sz = hn::Zero(d);
    }

    HWY_INLINE void addBatch(const SurfaceStressPass& p, std::size_t first) {
        const PairBatch b = loadPairs<Wide>(p.k, p.neighborRecords, xi, yi, zi, list, first);
        const FloatVec f = spikyGradientFactor(p.k.h, p.gradientCoefficient, b);
        const FloatVec wx = hn::Mul(b.dx, f), wy = hn::Mul(b.dy, f), wz = hn::Mul(b.dz, f);
        const GatheredStress tj =
            gatherStress<Wide>(p.neighborStress, list.entries + (Wide ? 2 : 1) * first);
        const FloatVec xx = hn::Add(ti.xx, tj.xx), yy = hn::Add(ti.yy, tj.yy),
                       zz = hn::Add(ti.zz, tj.zz), xy = hn::Add(ti.xy, tj.xy),
                       xz = hn::Add(ti.xz, tj.xz), yz = hn::Add(ti.yz, tj.yz);
        // Lanes outside the support (f = 0) add nothing, whatever their T_j.
        const FloatMask on = hn::Ne(f, hn::Zero(FloatTag{}));
        const auto row = [&](FloatVec a, FloatVec bb, FloatVec cc) {
            return hn::IfThenElseZero(
                on, hn::Add(hn::Add(hn::Mul(a, wx), hn::Mul(bb, wy)), hn::Mul(cc, wz)));
        };
        sx = hn::Add(sx, row(xx, xy, xz));
        sy = hn::Add(sy, row(xy, yy, yz));
        sz = hn::Add(sz, row(xz, yz, zz));
    }

    HWY_INLINE void finish(const SurfaceStressPass& p, std::size_t i) const {
        const Vec3 dv = reference::surfaceStressVelocityChange(
            p.c, p.dt, Vec3{sumOfLanes(sx), sumOfLanes(sy), sumOfLanes(sz)});
        p.velocity->set(i, p.velocity->get(i) + dv);
    }
};

SurfaceStressPass makePass(const SolverConstants& c, const SolidSet* solids, float dt,
                           const NeighborSearch& search, const PackedPoint* predicted,
                           const Sym3* stress, Sym3* stressOut, Float3Array* velocity,
                           const NeighborList& block) {
    const FloatTag d;
    return {c,
            solids,
            dt,
            search,
            predicted,
            predicted + block.base,
            stress,
            stress ? stress + block.base : nullptr,
            stressOut,
            velocity,
            pairConstants(c.h, c.poly6.h2),
            hn::Set(d, c.spiky.gradientCoefficient),
            hn::Set(d, c.particleMass / c.restDensity)};
}

void SurfaceStress(const SolverConstants& c, const SolidSet* solids, const NeighborSearch& search,
                   const PackedPoint* predicted, Sym3* stress, std::size_t begin, std::size_t end) {
    forEachListBlock(
        search, begin, end, [&](std::size_t first, std::size_t last, const NeighborList& block) {
            const SurfaceStressPass pass =
                makePass(c, solids, 0.0f, search, predicted, nullptr, stress, nullptr, block);
            if (block.wide)
                forEachParticleInterleaved<StressParticle<true>>(pass, first, last);
            else
                forEachParticleInterleaved<StressParticle<false>>(pass, first, last);
        });
}

void SurfaceStressForce(const SolverConstants& c, float dt, const NeighborSearch& search,
                        const PackedPoint* predicted, const Sym3* stress, Float3Array& velocity,
                        std::size_t begin, std::size_t end) {
    forEachListBlock(
        search, begin, end, [&](std::size_t first, std::size_t last, const NeighborList& block) {
            const SurfaceStressPass pass =
                makePass(c, nullptr, dt, search, predicted, stress, nullptr, &velocity, block);
            if (block.wide)
                forEachParticleInterleaved<ForceParticle<true>>(pass, first, last);
            else
                forEachParticleInterleaved<ForceParticle<false>>(pass, first, last);
        });
}

}  // namespace pbf::stages::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace pbf::stages {

HWY_EXPORT(SurfaceStress);
HWY_EXPORT(SurfaceStressForce);

void computeSurfaceStress(const SolverConstants& c, const SolidSet* solids,
                          const NeighborSearch& search, const PackedPoint* predicted, Sym3* stress,
                          std::size_t begin, std::size_t end) {
    HWY_DYNAMIC_DISPATCH(SurfaceStress)(c, solids, search, predicted, stress, begin, end);
}

void applySurfaceStress(const SolverConstants& c, float dt, const NeighborSearch& search,
                        const PackedPoint* predicted, const Sym3* stress, Float3Array& velocity,
                        std::size_t begin, std::size_t end) {
    HWY_DYNAMIC_DISPATCH(SurfaceStressForce)
    (c, dt, search, predicted, stress, velocity, begin, end);
}

}  // namespace pbf::stages
#endif  // HWY_ONCE
