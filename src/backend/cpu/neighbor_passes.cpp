// The SIMD neighbour passes of the solver (density + lambda, position
// correction, XSPH + vorticity), compiled once per instruction set target by
// Highway's foreach_target (see simd-inl.h) and called through Highway's
// dispatch: the host's target in native builds, the best one the CPU has in
// portable builds.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "backend/cpu/neighbor_passes.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>

#include "backend/boundary.hpp"
#include "backend/cpu/simd-inl.h"
// After simd-inl.h: the neighbour-batch helpers (per target, like it).
#include "backend/cpu/pair_loops-inl.h"
#include "backend/cpu/solver_stages.hpp"
#include "backend/reactions.hpp"
#include "core/iteration_control.hpp"

HWY_BEFORE_NAMESPACE();
namespace pbf::stages::HWY_NAMESPACE {

namespace hn = hwy::HWY_NAMESPACE;
using namespace pbf::simd::HWY_NAMESPACE;
using boundary::addSolidContribution;
using boundary::addWallContribution;
using boundary::clampToBox;

// x^E by squaring: the shortest chain of multiplications.
template <int E>
HWY_INLINE FloatVec integerPower(FloatVec x) {
    if constexpr (E == 1) {
        return x;
    } else if constexpr (E % 2 == 0) {
        const FloatVec half = integerPower<E / 2>(x);
        return hn::Mul(half, half);
    } else {
        return hn::Mul(x, integerPower<E - 1>(x));
    }
}

struct DensityPass {
    const SolverConstants& c;
    const SolidSet* solids;
    const NeighborSearch& search;
    const PackedPoint* predicted;
    const PackedPoint* neighborRecords;  // predicted + the block's list base
    float* density;
    PackedPoint* withLambda;
    PairConstants k;
    float gradScale;  // grad C = m/rho0 grad W
    float spiky;
    std::int64_t*
        compression;  // sum of C_i over the range, fixed point (core/iteration_control.hpp)
};

template <bool Wide>
struct DensityParticle {
    FloatVec xi, yi, zi;
    NeighborList list;
    FloatVec kernel, gx, gy, gz, gradSquared;

    HWY_INLINE DensityParticle(const DensityPass& p, std::size_t i) : list(p.search.neighbors(i)) {
        const FloatTag d;
        xi = hn::Set(d, p.predicted[i].x);
        yi = hn::Set(d, p.predicted[i].y);
        zi = hn::Set(d, p.predicted[i].z);
        kernel = gx = gy = gz = gradSquared = hn::Zero(d);
    }

    HWY_INLINE void addBatch(const DensityPass& p, std::size_t first) {
        const PairBatch b = loadPairs<Wide>(p.k, p.neighborRecords, xi, yi, zi, list, first);
        kernel = hn::Add(kernel, poly6Shape(p.k, b));
        FloatVec dd2;
        const FloatVec g = spikyShapeOverR(p.k, b, dd2);
        gx = hn::MulAdd(g, b.dx, gx);
        gy = hn::MulAdd(g, b.dy, gy);
        gz = hn::MulAdd(g, b.dz, gz);
        // |grad W|^2 = (coefficient (h - r)^2)^2: no division needed.
        gradSquared = hn::MulAdd(dd2, dd2, gradSquared);
    }

    HWY_INLINE void finish(const DensityPass& p, std::size_t i) const {
        const SolverConstants& c = p.c;
        const Vec3 x{p.predicted[i].x, p.predicted[i].y, p.predicted[i].z};
        float kernelSum = c.poly6.coefficient * sumOfLanes(kernel) + c.poly6.value(0.0f);
        const float gradSquaredSum = p.spiky * p.spiky * sumOfLanes(gradSquared);
        // The walls are fixed: they add to rho_i and to grad_i C_i, but have
        // no gradient terms of their own.
        Vec3 gradI = Vec3{sumOfLanes(gx), sumOfLanes(gy), sumOfLanes(gz)} * p.spiky;
        Vec3 wallGradient{};
        addWallContribution(c, x, kernelSum, wallGradient);
        addSolidContribution(c, p.solids, x, kernelSum, wallGradient);
        gradI += wallGradient * p.gradScale;
        const float rho = c.particleMass * kernelSum;
        p.density[i] = rho;
        const float constraint = std::max(rho * c.inverseRestDensity - 1.0f, 0.0f);
        *p.compression += fixedPointCompression(constraint);
        const float lambdaI =
            -constraint / (lengthSquared(gradI) + gradSquaredSum + c.relaxationEpsilon);
        p.withLambda[i] = {x.x, x.y, x.z, lambdaI};
    }
};

std::int64_t DensityAndLambda(const SolverStep& s, std::size_t begin, std::size_t end) {
    const SolverConstants& c = s.context.constants;
    const SolidSet* solids = s.solids;
    const NeighborSearch& search = s.search;
    const PackedPoint* predicted = s.predicted;
    float* density = s.particles.density.data();
    PackedPoint* withLambda = s.withLambda;
    const float gradScale = c.particleMass * c.inverseRestDensity;
    std::int64_t compression = 0;
    forEachListBlock(search, begin, end,
                     [&](std::size_t first, std::size_t last, const NeighborList& block) {
                         const DensityPass pass{c,
                                                solids,
                                                search,
                                                predicted,
                                                predicted + block.base,
                                                density,
                                                withLambda,
                                                pairConstants(c.h, c.poly6.h2),
                                                gradScale,
                                                c.spiky.gradientCoefficient * gradScale,
                                                &compression};
                         if (block.wide)
                             forEachParticleInterleaved<DensityParticle<true>>(pass, first, last);
                         else
                             forEachParticleInterleaved<DensityParticle<false>>(pass, first, last);
                     });
    return compression;
}

struct CorrectionPass {
    const SolverConstants& c;
    const SolidSet* solids;
    ReactionAccumulator* reactions;  // null: no coupled solid
    const NeighborSearch& search;
    const Float3Array& start;
    const PackedPoint* withLambda;
    const PackedPoint* neighborRecords;  // withLambda + the block's list base
    PackedPoint* corrected;
    PairConstants k;
    FloatVec ratioScale;  // poly6 coefficient / W(dq)
    FloatVec scorrScale;
};

// The correction for a compile-time s_corr exponent: (W/W(dq))^n as
// straight multiplications.
template <int Exponent, bool Wide>
struct CorrectionParticle {
    FloatVec xi, yi, zi, lambdaI;
    NeighborList list;
    FloatVec sx, sy, sz;

    HWY_INLINE CorrectionParticle(const CorrectionPass& p, std::size_t i)
        : list(p.search.neighbors(i)) {
        const FloatTag d;
        const PackedPoint& x = p.withLambda[i];
        xi = hn::Set(d, x.x);
        yi = hn::Set(d, x.y);
        zi = hn::Set(d, x.z);
        lambdaI = hn::Set(d, x.w * p.c.ownLambdaWeight);  // the pair term's share of lambda_i
        sx = sy = sz = hn::Zero(d);
    }

    HWY_INLINE void addBatch(const CorrectionPass& p, std::size_t first) {
        const PairBatch b = loadPairs<Wide>(p.k, p.neighborRecords, xi, yi, zi, list, first);
        // Artificial pressure (eq. 13): a small repulsion that keeps
        // particles from clumping where the constraint is inactive.
        const FloatVec ratio = hn::Mul(poly6Shape(p.k, b), p.ratioScale);
        const FloatVec power = integerPower<Exponent>(ratio);
        FloatVec dd2;
        const FloatVec g = spikyShapeOverR(p.k, b, dd2);
        const FloatVec lambdaSum = hn::Add(lambdaI, b.w);  // w holds lambda_j
        const FloatVec weight = hn::Mul(g, hn::MulAdd(p.scorrScale, power, lambdaSum));
        sx = hn::MulAdd(weight, b.dx, sx);
        sy = hn::MulAdd(weight, b.dy, sy);
        sz = hn::MulAdd(weight, b.dz, sz);
    }

    HWY_INLINE void finish(const CorrectionPass& p, std::size_t i) const {
        const SolverConstants& c = p.c;
        const PackedPoint& packed = p.withLambda[i];
        const Vec3 x{packed.x, packed.y, packed.z};
        const float massOverRho0 = c.particleMass * c.inverseRestDensity;
        Vec3 dp = Vec3{sumOfLanes(sx), sumOfLanes(sy), sumOfLanes(sz)} *
                  (massOverRho0 * c.spiky.gradientCoefficient);
        // The walls' and solids' share of grad_i C_i (they carry no lambda of their own).
        float unusedKernelSum = 0.0f;
        Vec3 wallGradient{};
        addWallContribution(c, x, unusedKernelSum, wallGradient);
        boundary::SolidContribution solid;
        if (p.solids) solid = boundary::solidContribution(c, *p.solids, x);
        // Over-relaxation (Macklin et al. 2014, sec. 4.2) scales the whole
        // correction, the boundary's share included (and so its reaction).
        const float boundaryScale = packed.w * massOverRho0 * c.overRelaxation;
        dp = dp * c.overRelaxation + (wallGradient + solid.gradient) * boundaryScale;
        // x* + dp, projected into the collision box and out of the solids
        // (Alg. 1 l. 16-18).
        Vec3 moved = clampToBox(c.collisionBox, x + dp);
        if (p.solids) {
            const Vec3 unprojected = moved;
            std::size_t touched = boundary::kNoSolid;
            moved = boundary::resolveSolidCollision(c, *p.solids, p.start.get(i), moved, &touched);
            // Two-way coupling: what a body's boundary did to particle i
            // (backend/reactions.hpp).
            if (p.reactions) {
                p.reactions->add(i, solid.solid, x, solid.gradient * boundaryScale);
                p.reactions->add(i, touched, moved, moved - unprojected);
            }
        }
        p.corrected[i] = {moved.x, moved.y, moved.z, 0.0f};
    }
};

// [begin, end) lies in one neighbour-list block.
template <int Exponent>
void positionCorrectionRange(const CorrectionPass& pass, std::size_t begin, std::size_t end) {
    if (pass.search.neighbors(begin).wide)
        forEachParticleInterleaved<CorrectionParticle<Exponent, true>>(pass, begin, end);
    else
        forEachParticleInterleaved<CorrectionParticle<Exponent, false>>(pass, begin, end);
}

void CorrectPositions(const SolverStep& s, std::size_t begin, std::size_t end) {
    const SolverConstants& c = s.context.constants;
    const SolidSet* solids = s.solids;
    ReactionAccumulator* reactions = s.reactions;
    const NeighborSearch& search = s.search;
    const Float3Array& start = s.particles.position;
    const PackedPoint* withLambda = s.withLambda;
    PackedPoint* corrected = s.predicted;
    const FloatTag d;
    // One instantiation per exponent allowed by validate() (n in [1, 8]).
    using Range = void (*)(const CorrectionPass&, std::size_t, std::size_t);
    static constexpr Range kByExponent[] = {
        &positionCorrectionRange<1>, &positionCorrectionRange<2>, &positionCorrectionRange<3>,
        &positionCorrectionRange<4>, &positionCorrectionRange<5>, &positionCorrectionRange<6>,
        &positionCorrectionRange<7>, &positionCorrectionRange<8>};
    const Range range = kByExponent[std::clamp(c.scorrExponent, 1, 8) - 1];
    forEachListBlock(
        search, begin, end, [&](std::size_t first, std::size_t last, const NeighborList& block) {
            const CorrectionPass pass{c,
                                      solids,
                                      reactions,
                                      search,
                                      start,
                                      withLambda,
                                      withLambda + block.base,
                                      corrected,
                                      pairConstants(c.h, c.poly6.h2),
                                      hn::Set(d, c.poly6.coefficient * c.scorrInverseWdq),
                                      hn::Set(d, c.scorrScale)};
            range(pass, first, last);
        });
}

// [begin, end) lies in one neighbour-list block.
template <bool Wide>
void viscosityAndVorticityRange(const SolverConstants& c, float viscosity,
                                const NeighborSearch& search, const PackedPoint* predicted,
                                const PackedPoint* velocityDensity, Float3Array* vorticity,
                                Float3Array& velocity, std::size_t begin, std::size_t end) {
    const std::uint32_t base = search.neighbors(begin).base;
    const bool withVorticity = vorticity != nullptr;
    const FloatTag d;
    const std::size_t lanes = hn::Lanes(d);
    const PairConstants k = pairConstants(c.h, c.poly6.h2);
    const float mass = c.particleMass;
    const FloatVec one = hn::Set(d, 1.0f);
    for (std::size_t i = begin; i < end; ++i) {
        const PackedPoint& x = predicted[i];
        const PackedPoint& v = velocityDensity[i];
        const FloatVec vxi = hn::Set(d, x.x), vyi = hn::Set(d, x.y), vzi = hn::Set(d, x.z);
        const FloatVec uxi = hn::Set(d, v.x), uyi = hn::Set(d, v.y), uzi = hn::Set(d, v.z);
        const FloatVec rhoI = hn::Set(d, v.w);
        const NeighborList nbrs = search.neighbors(i);
        FloatVec dvx = hn::Zero(d), dvy = hn::Zero(d), dvz = hn::Zero(d);
        FloatVec ox = hn::Zero(d), oy = hn::Zero(d), oz = hn::Zero(d);
        for (std::size_t first = 0; first < nbrs.size(); first += lanes) {
            const PairBatch b = loadPairs<Wide>(k, predicted + base, vxi, vyi, vzi, nbrs, first);
            const Gathered4 vj =
                gather4<Wide>(&velocityDensity[base].x, nbrs.entries + (Wide ? 2 : 1) * first);
            const FloatVec wx = hn::Sub(vj.x, uxi), wy = hn::Sub(vj.y, uyi),
                           wz = hn::Sub(vj.z, uzi);
            const FloatVec rhoJ = vj.w;
            // XSPH with the symmetric volume 2 m / (rho_i + rho_j): pairwise
            // equal and opposite, so momentum is conserved.
            const FloatVec xsph = hn::Div(poly6Shape(k, b), hn::Add(rhoI, rhoJ));
            dvx = hn::MulAdd(wx, xsph, dvx);
            dvy = hn::MulAdd(wy, xsph, dvy);
            dvz = hn::MulAdd(wz, xsph, dvz);
            if (withVorticity) {
                // omega_i += V_j grad_i W_ij x (v_j - v_i)
                FloatVec dd2;
                const FloatVec g = hn::Mul(spikyShapeOverR(k, b, dd2), hn::Div(one, rhoJ));
                const FloatVec gx = hn::Mul(g, b.dx), gy = hn::Mul(g, b.dy), gz = hn::Mul(g, b.dz);
                ox = hn::Add(ox, hn::Sub(hn::Mul(gy, wz), hn::Mul(gz, wy)));
                oy = hn::Add(oy, hn::Sub(hn::Mul(gz, wx), hn::Mul(gx, wz)));
                oz = hn::Add(oz, hn::Sub(hn::Mul(gx, wy), hn::Mul(gy, wx)));
            }
        }
        const float xsphScale = 2.0f * mass * c.poly6.coefficient * viscosity;
        const float vorticityScale = c.spiky.gradientCoefficient * mass;
        if (withVorticity)
            vorticity->set(i,
                           Vec3{sumOfLanes(ox), sumOfLanes(oy), sumOfLanes(oz)} * vorticityScale);
        // The neighbours read v from the packed copy: v_i can be updated in place.
        const Vec3 dv = Vec3{sumOfLanes(dvx), sumOfLanes(dvy), sumOfLanes(dvz)} * xsphScale;
        velocity.set(i, Vec3{v.x, v.y, v.z} + dv);
    }
}

void ViscosityAndVorticity(const SolverStep& s, std::size_t begin, std::size_t end) {
    const SolverConstants& c = s.context.constants;
    const float viscosity = s.context.params.fluid.viscosity;
    const NeighborSearch& search = s.search;
    const PackedPoint* predicted = s.predicted;
    const PackedPoint* velocityDensity = s.velocityDensity;
    Float3Array* vorticity = s.terms.vorticity ? s.vorticity : nullptr;
    Float3Array& velocity = s.particles.velocity;
    forEachListBlock(
        search, begin, end, [&](std::size_t first, std::size_t last, const NeighborList& block) {
            if (block.wide)
                viscosityAndVorticityRange<true>(c, viscosity, search, predicted, velocityDensity,
                                                 vorticity, velocity, first, last);
            else
                viscosityAndVorticityRange<false>(c, viscosity, search, predicted, velocityDensity,
                                                  vorticity, velocity, first, last);
        });
}

}  // namespace pbf::stages::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace pbf::stages {

HWY_EXPORT(DensityAndLambda);
HWY_EXPORT(CorrectPositions);
HWY_EXPORT(ViscosityAndVorticity);

std::int64_t computeDensityAndLambda(const SolverStep& s, std::size_t begin, std::size_t end) {
    return HWY_DYNAMIC_DISPATCH(DensityAndLambda)(s, begin, end);
}

void correctPositions(const SolverStep& s, std::size_t begin, std::size_t end) {
    HWY_DYNAMIC_DISPATCH(CorrectPositions)(s, begin, end);
}

void applyViscosityAndComputeVorticity(const SolverStep& s, std::size_t begin, std::size_t end) {
    HWY_DYNAMIC_DISPATCH(ViscosityAndVorticity)(s, begin, end);
}

}  // namespace pbf::stages
#endif  // HWY_ONCE
