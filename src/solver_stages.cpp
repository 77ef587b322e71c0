#include "solver_stages.hpp"

#include <algorithm>
#include <cmath>

#include "simd.hpp"

namespace pbf::stages {
namespace {

Vec3 clampToBox(const Aabb& box, const Vec3& p) {
    return {std::clamp(p.x, box.min.x, box.max.x), std::clamp(p.y, box.min.y, box.max.y),
            std::clamp(p.z, box.min.z, box.max.z)};
}

// Linear interpolation in the flat-wall table at distance s.
void sampleWallTable(const WallTable& w, float distance, float& kernel, float& gradient) {
    const float t = std::max(distance, 0.0f) * w.inverseStep;
    const int k = std::min(static_cast<int>(t), WallTable::kSamples - 1);
    const float f = t - float(k);
    kernel = w.kernelSum[k] + f * (w.kernelSum[k + 1] - w.kernelSum[k]);
    gradient = w.gradientSum[k] + f * (w.gradientSum[k + 1] - w.gradientSum[k]);
}

// Adds the walls of the domain box within reach of x: their kernel sum and
// the gradient of that sum with respect to x (pointing into the walls).
void addWallContribution(const SolverConstants& c, const Vec3& x, float& kernelSum,
                         Vec3& gradient) {
    const WallTable& w = c.wall;
    auto add = [&](float distance, float Vec3::*axis, float outward) {
        if (!(distance < w.range)) return;
        float kernel = 0.0f, slope = 0.0f;
        sampleWallTable(w, distance, kernel, slope);
        kernelSum += kernel;
        gradient.*axis += outward * slope;
    };
    add(x.x - c.domain.min.x, &Vec3::x, -1.0f);
    add(c.domain.max.x - x.x, &Vec3::x, 1.0f);
    add(x.y - c.domain.min.y, &Vec3::y, -1.0f);
    add(c.domain.max.y - x.y, &Vec3::y, 1.0f);
    add(x.z - c.domain.min.z, &Vec3::z, -1.0f);
    add(c.domain.max.z - x.z, &Vec3::z, 1.0f);
}

// The nearest solid within reach adds the flat-wall density at its signed
// distance, and its gradient along the surface normal (into the solid).
void addSolidContribution(const SolverConstants& c, const SolidSet* solids, const Vec3& x,
                          float& kernelSum, Vec3& gradient) {
    if (!solids) return;
    Vec3 normal;
    const float distance = solids->signedDistance(x, c.wall.range, normal);
    if (!(distance < c.wall.range)) return;
    float kernel = 0.0f, slope = 0.0f;
    sampleWallTable(c.wall, distance, kernel, slope);
    kernelSum += kernel;
    gradient -= normal * slope;
}

}  // namespace

void predictPositions(const Vec3& gravity, float dt, const Aabb& box, const Float3Array& position,
                      Float3Array& velocity, Float3Array& predicted, std::size_t begin,
                      std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
        const Vec3 v = velocity.get(i) + dt * gravity;
        velocity.set(i, v);
        predicted.set(i, clampToBox(box, position.get(i) + dt * v));
    }
}

// The neighbour loops below run on full SIMD vectors of neighbours
// (simd.hpp): gather x_j, mask the lanes past the list's end and those
// outside the kernel's support, accumulate per lane, one tree sum at the end.
// Constant factors (the kernels' coefficients) are applied once per particle.

namespace {

using namespace simd;

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

PairConstants pairConstants(float h, float h2) {
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
        const float lambdaI =
            -constraint / (lengthSquared(gradI) + gradSquaredSum + c.relaxationEpsilon);
        p.withLambda[i] = {x.x, x.y, x.z, lambdaI};
    }
};

}  // namespace

void computeDensityAndLambda(const SolverConstants& c, const SolidSet* solids,
                             const NeighborSearch& search, const PackedPoint* predicted,
                             float* density, PackedPoint* withLambda, std::size_t begin,
                             std::size_t end) {
    const float gradScale = c.particleMass * c.inverseRestDensity;
    const NeighborList block = search.neighbors(begin);
    const DensityPass pass{c,
                           solids,
                           search,
                           predicted,
                           predicted + block.base,
                           density,
                           withLambda,
                           pairConstants(c.h, c.poly6.h2),
                           gradScale,
                           c.spiky.gradientCoefficient * gradScale};
    if (block.wide)
        forEachParticleInterleaved<DensityParticle<true>>(pass, begin, end);
    else
        forEachParticleInterleaved<DensityParticle<false>>(pass, begin, end);
}

namespace {

struct CorrectionPass {
    const SolverConstants& c;
    const SolidSet* solids;
    float radius;
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
        lambdaI = hn::Set(d, x.w);
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
        // The walls' share of grad_i C_i (they carry no lambda of their own).
        float unusedKernelSum = 0.0f;
        Vec3 wallGradient{};
        addWallContribution(c, x, unusedKernelSum, wallGradient);
        addSolidContribution(c, p.solids, x, unusedKernelSum, wallGradient);
        dp += wallGradient * (packed.w * massOverRho0);
        // x* + dp, projected into the collision box and out of the solids
        // (Alg. 1 l. 16-18).
        Vec3 moved = clampToBox(c.collisionBox, x + dp);
        if (p.solids) moved = resolveSolidCollision(c, *p.solids, p.radius, p.start.get(i), moved);
        p.corrected[i] = {moved.x, moved.y, moved.z, 0.0f};
    }
};

template <int Exponent>
void positionCorrectionRange(const CorrectionPass& pass, std::size_t begin, std::size_t end) {
    if (pass.search.neighbors(begin).wide)
        forEachParticleInterleaved<CorrectionParticle<Exponent, true>>(pass, begin, end);
    else
        forEachParticleInterleaved<CorrectionParticle<Exponent, false>>(pass, begin, end);
}

}  // namespace

void correctPositions(const SolverConstants& c, const SolidSet* solids, float radius,
                      const NeighborSearch& search, const Float3Array& start,
                      const PackedPoint* withLambda, PackedPoint* corrected, std::size_t begin,
                      std::size_t end) {
    const FloatTag d;
    const CorrectionPass pass{c,
                              solids,
                              radius,
                              search,
                              start,
                              withLambda,
                              withLambda + search.neighbors(begin).base,
                              corrected,
                              pairConstants(c.h, c.poly6.h2),
                              hn::Set(d, c.poly6.coefficient * c.scorrInverseWdq),
                              hn::Set(d, c.scorrScale)};
    // One instantiation per exponent allowed by validate() (n in [1, 8]).
    using Range = void (*)(const CorrectionPass&, std::size_t, std::size_t);
    static constexpr Range kByExponent[] = {
        &positionCorrectionRange<1>, &positionCorrectionRange<2>, &positionCorrectionRange<3>,
        &positionCorrectionRange<4>, &positionCorrectionRange<5>, &positionCorrectionRange<6>,
        &positionCorrectionRange<7>, &positionCorrectionRange<8>};
    kByExponent[std::clamp(c.scorrExponent, 1, 8) - 1](pass, begin, end);
}

void packPositions(const Float3Array& predicted, PackedPoint* packed, std::size_t begin,
                   std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
        packed[i] = {predicted.x[i], predicted.y[i], predicted.z[i], 0.0f};
}

void unpackPositions(const PackedPoint* packed, Float3Array& predicted, std::size_t begin,
                     std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
        predicted.set(i, {packed[i].x, packed[i].y, packed[i].z});
}

void updateVelocity(float inverseDt, const Float3Array& position, const Float3Array& predicted,
                    const float* density, Float3Array& velocity, PackedPoint* velocityDensity,
                    std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
        const Vec3 v = (predicted.get(i) - position.get(i)) * inverseDt;
        velocity.set(i, v);
        velocityDensity[i] = {v.x, v.y, v.z, density[i]};
    }
}

namespace {

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

}  // namespace

void applyViscosityAndComputeVorticity(const SolverConstants& c, float viscosity,
                                       const NeighborSearch& search, const PackedPoint* predicted,
                                       const PackedPoint* velocityDensity, Float3Array* vorticity,
                                       Float3Array& velocity, std::size_t begin, std::size_t end) {
    if (search.neighbors(begin).wide)
        viscosityAndVorticityRange<true>(c, viscosity, search, predicted, velocityDensity,
                                         vorticity, velocity, begin, end);
    else
        viscosityAndVorticityRange<false>(c, viscosity, search, predicted, velocityDensity,
                                          vorticity, velocity, begin, end);
}

void applyVorticityConfinement(const SolverConstants& c, float vorticityEpsilon, float dt,
                               const NeighborSearch& search, const Float3Array& predicted,
                               const Float3Array& vorticity, const float* density,
                               Float3Array& velocity, std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
        Vec3 v = velocity.get(i);
        {
            const Vec3 xi = predicted.get(i);
            const Vec3 omegaI = vorticity.get(i);
            const float magnitudeI = length(omegaI);
            Vec3 eta{};  // gradient of |omega| (SPH difference form)
            const NeighborList nbrs = search.neighbors(i);
            for (std::size_t k = 0; k < nbrs.size(); ++k) {
                const std::uint32_t j = nbrs[k];
                const Vec3 rij = xi - predicted.get(j);
                const float r = length(rij);
                const float volumeJ = c.particleMass / density[j];
                eta +=
                    c.spiky.gradient(rij, r) * ((length(vorticity.get(j)) - magnitudeI) * volumeJ);
            }
            const float etaLength = length(eta);
            if (etaLength > 1e-20f) {
                const Vec3 normal = eta * (1.0f / etaLength);
                v += cross(normal, omegaI) * (dt * vorticityEpsilon * c.h * magnitudeI);
            }
        }
        velocity.set(i, v);
    }
}

void respondToWalls(const Aabb& box, float restitution, float friction,
                    const Float3Array& predicted, Float3Array& velocity, std::size_t begin,
                    std::size_t end) {
    const float tolerance =
        1e-4f * std::max(1e-6f, box.extent().x + box.extent().y + box.extent().z);
    for (std::size_t i = begin; i < end; ++i) {
        const Vec3 x = predicted.get(i);
        Vec3 v = velocity.get(i);
        for (int axis = 0; axis < 3; ++axis) {
            float* vn = axis == 0 ? &v.x : (axis == 1 ? &v.y : &v.z);
            const bool onMin = x[axis] <= box.min[axis] + tolerance && *vn < 0.0f;
            const bool onMax = x[axis] >= box.max[axis] - tolerance && *vn > 0.0f;
            if (!onMin && !onMax) continue;
            const float normalSpeed = std::fabs(*vn);
            *vn = -restitution * *vn;
            // Coulomb friction: the tangential speed drops by mu times the
            // normal speed change, never below zero.
            float* t1 = axis == 0 ? &v.y : &v.x;
            float* t2 = axis == 2 ? &v.y : &v.z;
            const float tangential = std::sqrt(*t1 * *t1 + *t2 * *t2);
            if (tangential > 0.0f) {
                const float keep = std::max(
                    0.0f, 1.0f - friction * (1.0f + restitution) * normalSpeed / tangential);
                *t1 *= keep;
                *t2 *= keep;
            }
        }
        velocity.set(i, v);
    }
}

Vec3 resolveSolidCollision(const SolverConstants& c, const SolidSet& solids, float radius,
                           const Vec3& start, Vec3 x) {
    const float reach = c.h;
    const float hitDistance = 0.05f * radius;
    Vec3 normal;
    const Vec3 move = x - start;
    const float moveLength = length(move);
    // Sweep: sphere-trace from the start; the distance field guarantees no
    // surface closer than d, so each step of length d is safe.
    const float startDistance = solids.signedDistance(start, moveLength + reach, normal);
    if (startDistance < moveLength && moveLength > 0.0f) {
        const Vec3 direction = move * (1.0f / moveLength);
        float travelled = std::max(startDistance, 0.0f);
        bool hit = startDistance <= hitDistance;
        for (int step = 0; step < 64 && !hit && travelled < moveLength; ++step) {
            const float d =
                solids.signedDistance(start + direction * travelled, moveLength + reach, normal);
            if (d <= hitDistance) {
                hit = true;
                break;
            }
            travelled += d;
        }
        if (hit) x = start + direction * std::min(travelled, moveLength);
    }
    // Push out to one radius (twice: a corner between two solids).
    for (int pass = 0; pass < 2; ++pass) {
        const float d = solids.signedDistance(x, reach, normal);
        if (!(d < radius)) break;
        x += normal * (radius - d);
    }
    return clampToBox(c.collisionBox, x);
}

void resolveSolidCollisions(const SolverConstants& c, const SolidSet& solids, float radius,
                            const Float3Array& position, Float3Array& predicted, std::size_t begin,
                            std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
        predicted.set(i,
                      resolveSolidCollision(c, solids, radius, position.get(i), predicted.get(i)));
}

void respondToSolids(const SolidSet& solids, float radius, float restitution, float friction,
                     const Float3Array& predicted, Float3Array& velocity, std::size_t begin,
                     std::size_t end) {
    const float contact = 1.05f * radius;
    for (std::size_t i = begin; i < end; ++i) {
        Vec3 normal;
        if (!(solids.signedDistance(predicted.get(i), contact, normal) < contact)) continue;
        Vec3 v = velocity.get(i);
        const float vn = dot(v, normal);
        if (vn >= 0.0f) continue;  // separating
        const Vec3 tangential = v - normal * vn;
        const float tangentialSpeed = length(tangential);
        const float keep =
            tangentialSpeed > 0.0f
                ? std::max(0.0f, 1.0f - friction * (1.0f + restitution) * -vn / tangentialSpeed)
                : 0.0f;
        v = tangential * keep - normal * (restitution * vn);
        velocity.set(i, v);
    }
}

void commitPositions(const Float3Array& predicted, Float3Array& position, std::size_t begin,
                     std::size_t end) {
    std::copy(predicted.x.begin() + begin, predicted.x.begin() + end, position.x.begin() + begin);
    std::copy(predicted.y.begin() + begin, predicted.y.begin() + end, position.y.begin() + begin);
    std::copy(predicted.z.begin() + begin, predicted.z.begin() + end, position.z.begin() + begin);
}

}  // namespace pbf::stages
