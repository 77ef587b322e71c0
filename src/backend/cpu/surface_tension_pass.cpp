// The SIMD pass of surface tension: every particle's cohesion (the pair
// force of the surface layer) from its neighbours at the end-of-step
// positions x* plus the walls' and solids' adhesion, added to its velocity
// (v += dt a), the surface layer's weights s read from the packed records.
// The scalar equations are reference::cohesionTerm and
// reference::adhesionAcceleration (backend/reference/equations.hpp,
// "Surface tension and adhesion").
// Compiled once per instruction set target like neighbor_passes.cpp.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "backend/cpu/surface_tension_pass.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include <cstddef>

#include "backend/boundary.hpp"
#include "backend/cpu/simd-inl.h"
// After simd-inl.h: the neighbour-batch helpers (per target, like it).
#include "backend/cpu/pair_loops-inl.h"
#include "backend/cpu/solver_stages.hpp"
#include "backend/reactions.hpp"
#include "backend/reference/equations.hpp"

HWY_BEFORE_NAMESPACE();
namespace pbf::stages::HWY_NAMESPACE {

namespace hn = hwy::HWY_NAMESPACE;
using namespace pbf::simd::HWY_NAMESPACE;

struct SurfaceTensionPass {
    const SolverConstants& c;
    float wallAdhesion;
    const SolidSet* solids;
    float dt;
    ReactionAccumulator* reactions;  // null: no coupled solid
    const NeighborSearch& search;
    const PackedPoint* positionLayer;    // (x*, s)
    const PackedPoint* neighborRecords;  // positionLayer + the block's list base
    Float3Array& velocity;
    PairConstants k;
    FloatVec minDistance2;   // d^2: no pull within one spacing
    FloatVec coreDistance2;  // r_c^2: pushed apart within it
    FloatVec coreDistance;
    FloatVec minusTwoCoreScale;
};

template <bool Wide>
struct CohesionParticle {
    FloatVec xi, yi, zi, surfaceI;
    NeighborList list;
    FloatVec ax, ay, az;

    HWY_INLINE CohesionParticle(const SurfaceTensionPass& p, std::size_t i)
        : list(p.search.neighbors(i)) {
        const FloatTag d;
        const PackedPoint& x = p.positionLayer[i];
        xi = hn::Set(d, x.x);
        yi = hn::Set(d, x.y);
        zi = hn::Set(d, x.z);
        surfaceI = hn::Set(d, x.w);
        ax = ay = az = hn::Zero(d);
    }

    HWY_INLINE void addBatch(const SurfaceTensionPass& p, std::size_t first) {
        const PairBatch b = loadPairs<Wide>(p.k, p.neighborRecords, xi, yi, zi, list, first);
        // reference::cohesionWeight; w holds s_j.
        const FloatVec q = hn::Sub(p.k.h2, b.r2);
        const FloatVec r = hn::Mul(b.r2, b.inverseR);
        const FloatVec coreGap = hn::Sub(p.coreDistance, r);
        const FloatVec core = hn::Mul(hn::Mul(coreGap, coreGap), b.inverseR);
        const FloatMask pulls = hn::And(b.inside, hn::Gt(b.r2, p.minDistance2));
        const FloatMask pushes = hn::And(b.inside, hn::Lt(b.r2, p.coreDistance2));
        const FloatVec weight = hn::IfThenElse(
            pushes, hn::Mul(p.minusTwoCoreScale, core),
            hn::IfThenElseZero(pulls, hn::Mul(hn::Mul(q, q), hn::Add(surfaceI, b.w))));
        ax = hn::MulAdd(weight, b.dx, ax);
        ay = hn::MulAdd(weight, b.dy, ay);
        az = hn::MulAdd(weight, b.dz, az);
    }

    HWY_INLINE void finish(const SurfaceTensionPass& p, std::size_t i) const {
        const SolverConstants& c = p.c;
        const Vec3 x{p.positionLayer[i].x, p.positionLayer[i].y, p.positionLayer[i].z};
        // -cohesionScale (s_i + s_j) (h^2 - r^2)^2 (x_i - x_j) summed, the scale applied once.
        const Vec3 cohesion =
            Vec3{sumOfLanes(ax), sumOfLanes(ay), sumOfLanes(az)} * -c.cohesionScale;
        const boundary::AdhesionPull pull = boundary::adhesionPull(c, p.wallAdhesion, p.solids, x);
        const Vec3 solid = reference::adhesionAcceleration(c, pull.solid);
        const Vec3 a = cohesion + reference::adhesionAcceleration(c, pull.walls) + solid;
        p.velocity.set(i, p.velocity.get(i) + p.dt * a);
        // Two-way coupling: a body's pull on the particle, as a move (dv dt).
        if (p.reactions) p.reactions->add(i, pull.solidIndex, x, (p.dt * p.dt) * solid);
    }
};

void SurfaceTension(const SolverStep& s, std::size_t begin, std::size_t end) {
    const SolverConstants& c = s.context.constants;
    const float wallAdhesion = s.context.params.solver.wallAdhesion;
    const SolidSet* solids = s.solids;
    const float dt = s.dt;
    ReactionAccumulator* reactions = s.reactions;
    const NeighborSearch& search = s.search;
    const PackedPoint* positionLayer = s.positionLayer;
    Float3Array& velocity = s.particles.velocity;
    const FloatTag d;
    forEachListBlock(search, begin, end,
                     [&](std::size_t first, std::size_t last, const NeighborList& block) {
                         const SurfaceTensionPass pass{c,
                                                       wallAdhesion,
                                                       solids,
                                                       dt,
                                                       reactions,
                                                       search,
                                                       positionLayer,
                                                       positionLayer + block.base,
                                                       velocity,
                                                       pairConstants(c.h, c.poly6.h2),
                                                       hn::Set(d, c.cohesionMinDistance2),
                                                       hn::Set(d, c.cohesionCoreDistance2),
                                                       hn::Set(d, c.cohesionCoreDistance),
                                                       hn::Set(d, -2.0f * c.cohesionCoreScale)};
                         if (block.wide)
                             forEachParticleInterleaved<CohesionParticle<true>>(pass, first, last);
                         else
                             forEachParticleInterleaved<CohesionParticle<false>>(pass, first, last);
                     });
}

}  // namespace pbf::stages::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace pbf::stages {

HWY_EXPORT(SurfaceTension);

void applySurfaceTension(const SolverStep& s, std::size_t begin, std::size_t end) {
    HWY_DYNAMIC_DISPATCH(SurfaceTension)(s, begin, end);
}

}  // namespace pbf::stages
#endif  // HWY_ONCE
