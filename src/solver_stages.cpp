#include "solver_stages.hpp"

#include <algorithm>
#include <cmath>

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

// The neighbour loops below accumulate into scalars under `omp simd`
// reductions so that the compiler vectorises them (gathering x_j). The
// vectorised order of additions is fixed by the code and the neighbour count
// alone, so results stay bit-identical across thread counts.

void computeDensityAndLambda(const SolverConstants& c, const SolidSet* solids,
                             const NeighborSearch& search, const Float3Array& predicted,
                             float* density, float* lambda, std::size_t begin, std::size_t end) {
    const float gradScale = c.particleMass * c.inverseRestDensity;  // grad C = m/rho0 grad W
    const float* px = predicted.x.data();
    const float* py = predicted.y.data();
    const float* pz = predicted.z.data();
    const float h = c.h, h2 = c.poly6.h2;
    const float poly6 = c.poly6.coefficient, spiky = c.spiky.gradientCoefficient * gradScale;
    for (std::size_t i = begin; i < end; ++i) {
        const float xi = px[i], yi = py[i], zi = pz[i];
        const std::span<const std::uint32_t> nbrs = search.neighbors(i);
        const std::uint32_t* nb = nbrs.data();
        const int count = static_cast<int>(nbrs.size());
        float kernelSum = 0.0f, gx = 0.0f, gy = 0.0f, gz = 0.0f, gradSquaredSum = 0.0f;
#pragma omp simd reduction(+ : kernelSum, gx, gy, gz, gradSquaredSum)
        for (int k = 0; k < count; ++k) {
            const std::uint32_t j = nb[k];
            const float dx = xi - px[j], dy = yi - py[j], dz = zi - pz[j];
            const float r2 = dx * dx + dy * dy + dz * dz;
            const float r = std::sqrt(r2);
            // Neighbours are closer than h by construction, but x* moved
            // since the lists were built: keep the kernels' support exact.
            const bool inside = r2 < h2 && r > 0.0f;
            const float d2 = h2 - r2;
            kernelSum += inside ? poly6 * d2 * d2 * d2 : 0.0f;
            const float d = h - r;
            const float g = inside ? spiky * d * d / r : 0.0f;  // grad C_i wrt x_j, scaled
            gx += g * dx;
            gy += g * dy;
            gz += g * dz;
            gradSquaredSum += g * g * r2;
        }
        kernelSum += c.poly6.value(0.0f);
        // The walls are fixed: they add to rho_i and to grad_i C_i, but have
        // no gradient terms of their own.
        Vec3 gradI{gx, gy, gz};
        Vec3 wallGradient{};
        addWallContribution(c, {xi, yi, zi}, kernelSum, wallGradient);
        addSolidContribution(c, solids, {xi, yi, zi}, kernelSum, wallGradient);
        gradI += wallGradient * gradScale;
        const float rho = c.particleMass * kernelSum;
        density[i] = rho;
        const float constraint = std::max(rho * c.inverseRestDensity - 1.0f, 0.0f);
        lambda[i] = -constraint / (lengthSquared(gradI) + gradSquaredSum + c.relaxationEpsilon);
    }
}

namespace {

// The correction loop for a compile-time s_corr exponent: (W/W(dq))^n as
// straight multiplications, so the loop has no call and vectorises.
template <int Exponent>
void positionCorrectionRange(const SolverConstants& c, const SolidSet* solids,
                             const NeighborSearch& search, const Float3Array& predicted,
                             const float* lambda, Float3Array& delta, std::size_t begin,
                             std::size_t end) {
    const float scale = c.particleMass * c.inverseRestDensity;
    const float* px = predicted.x.data();
    const float* py = predicted.y.data();
    const float* pz = predicted.z.data();
    const float h = c.h, h2 = c.poly6.h2;
    const float poly6 = c.poly6.coefficient, spiky = c.spiky.gradientCoefficient;
    const float scorrScale = c.scorrScale, inverseWdq = c.scorrInverseWdq;
    for (std::size_t i = begin; i < end; ++i) {
        const float xi = px[i], yi = py[i], zi = pz[i];
        const float lambdaI = lambda[i];
        const std::span<const std::uint32_t> nbrs = search.neighbors(i);
        const std::uint32_t* nb = nbrs.data();
        const int count = static_cast<int>(nbrs.size());
        float sx = 0.0f, sy = 0.0f, sz = 0.0f;
#pragma omp simd reduction(+ : sx, sy, sz)
        for (int k = 0; k < count; ++k) {
            const std::uint32_t j = nb[k];
            const float dx = xi - px[j], dy = yi - py[j], dz = zi - pz[j];
            const float r2 = dx * dx + dy * dy + dz * dz;
            const float r = std::sqrt(r2);
            const bool inside = r2 < h2 && r > 0.0f;
            const float d2 = h2 - r2;
            // Artificial pressure (eq. 13): a small repulsion that keeps
            // particles from clumping where the constraint is inactive.
            const float ratio = (inside ? poly6 * d2 * d2 * d2 : 0.0f) * inverseWdq;
            float power = ratio;
            for (int e = 1; e < Exponent; ++e) power *= ratio;
            const float d = h - r;
            const float g = inside ? spiky * d * d / r : 0.0f;
            const float weight = g * (lambdaI + lambda[j] + scorrScale * power);
            sx += weight * dx;
            sy += weight * dy;
            sz += weight * dz;
        }
        // The walls' share of grad_i C_i (they carry no lambda of their own).
        Vec3 dp{sx, sy, sz};
        float unusedKernelSum = 0.0f;
        Vec3 wallGradient{};
        addWallContribution(c, {xi, yi, zi}, unusedKernelSum, wallGradient);
        addSolidContribution(c, solids, {xi, yi, zi}, unusedKernelSum, wallGradient);
        dp += wallGradient * lambdaI;
        delta.set(i, dp * scale);
    }
}

}  // namespace

void computePositionCorrection(const SolverConstants& c, const SolidSet* solids,
                               const NeighborSearch& search, const Float3Array& predicted,
                               const float* lambda, Float3Array& delta, std::size_t begin,
                               std::size_t end) {
    // One instantiation per exponent allowed by validate() (n in [1, 8]).
    using Range =
        void (*)(const SolverConstants&, const SolidSet*, const NeighborSearch&, const Float3Array&,
                 const float*, Float3Array&, std::size_t, std::size_t);
    static constexpr Range kByExponent[] = {
        &positionCorrectionRange<1>, &positionCorrectionRange<2>, &positionCorrectionRange<3>,
        &positionCorrectionRange<4>, &positionCorrectionRange<5>, &positionCorrectionRange<6>,
        &positionCorrectionRange<7>, &positionCorrectionRange<8>};
    kByExponent[std::clamp(c.scorrExponent, 1, 8) - 1](c, solids, search, predicted, lambda, delta,
                                                       begin, end);
}

void applyPositionCorrection(const Aabb& box, const Float3Array& delta,
                             const Float3Array& predicted, Float3Array& corrected,
                             std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
        corrected.set(i, clampToBox(box, predicted.get(i) + delta.get(i)));
}

void updateVelocity(float inverseDt, const Float3Array& position, const Float3Array& predicted,
                    Float3Array& velocity, std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
        velocity.set(i, (predicted.get(i) - position.get(i)) * inverseDt);
}

void computeVorticityAndViscosity(const SolverConstants& c, float viscosity, bool withVorticity,
                                  const NeighborSearch& search, const Float3Array& predicted,
                                  const Float3Array& velocity, const float* density,
                                  Float3Array& vorticity, Float3Array& viscosityDelta,
                                  std::size_t begin, std::size_t end) {
    const float* px = predicted.x.data();
    const float* py = predicted.y.data();
    const float* pz = predicted.z.data();
    const float* vx = velocity.x.data();
    const float* vy = velocity.y.data();
    const float* vz = velocity.z.data();
    const float h = c.h, h2 = c.poly6.h2, mass = c.particleMass;
    const float poly6 = c.poly6.coefficient, spiky = c.spiky.gradientCoefficient;
    for (std::size_t i = begin; i < end; ++i) {
        const float xi = px[i], yi = py[i], zi = pz[i];
        const float vxi = vx[i], vyi = vy[i], vzi = vz[i];
        const float rhoI = density[i];
        const std::span<const std::uint32_t> nbrs = search.neighbors(i);
        const std::uint32_t* nb = nbrs.data();
        const int count = static_cast<int>(nbrs.size());
        float dvx = 0.0f, dvy = 0.0f, dvz = 0.0f;
        float ox = 0.0f, oy = 0.0f, oz = 0.0f;
        if (withVorticity) {
#pragma omp simd reduction(+ : dvx, dvy, dvz, ox, oy, oz)
            for (int k = 0; k < count; ++k) {
                const std::uint32_t j = nb[k];
                const float dx = xi - px[j], dy = yi - py[j], dz = zi - pz[j];
                const float r2 = dx * dx + dy * dy + dz * dz;
                const float r = std::sqrt(r2);
                const bool inside = r2 < h2 && r > 0.0f;
                const float wx = vx[j] - vxi, wy = vy[j] - vyi, wz = vz[j] - vzi;
                const float d2 = h2 - r2;
                const float w = inside ? poly6 * d2 * d2 * d2 : 0.0f;
                const float xsph = 2.0f * mass / (rhoI + density[j]) * w;
                dvx += wx * xsph;
                dvy += wy * xsph;
                dvz += wz * xsph;
                // omega_i += V_j grad_i W_ij x (v_j - v_i)
                const float d = h - r;
                const float g = inside ? spiky * d * d / r * (mass / density[j]) : 0.0f;
                const float gx = g * dx, gy = g * dy, gz = g * dz;
                ox += gy * wz - gz * wy;
                oy += gz * wx - gx * wz;
                oz += gx * wy - gy * wx;
            }
        } else {
#pragma omp simd reduction(+ : dvx, dvy, dvz)
            for (int k = 0; k < count; ++k) {
                const std::uint32_t j = nb[k];
                const float dx = xi - px[j], dy = yi - py[j], dz = zi - pz[j];
                const float r2 = dx * dx + dy * dy + dz * dz;
                const float d2 = h2 - r2;
                const float w = r2 < h2 ? poly6 * d2 * d2 * d2 : 0.0f;
                const float xsph = 2.0f * mass / (rhoI + density[j]) * w;
                dvx += (vx[j] - vxi) * xsph;
                dvy += (vy[j] - vyi) * xsph;
                dvz += (vz[j] - vzi) * xsph;
            }
        }
        vorticity.set(i, {ox, oy, oz});
        viscosityDelta.set(i, Vec3{dvx, dvy, dvz} * viscosity);
    }
}

void applyVorticityAndViscosity(const SolverConstants& c, float vorticityEpsilon, float dt,
                                const NeighborSearch& search, const Float3Array& predicted,
                                const Float3Array& vorticity, const float* density,
                                const Float3Array& viscosityDelta, Float3Array& velocity,
                                std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
        Vec3 v = velocity.get(i) + viscosityDelta.get(i);
        if (vorticityEpsilon > 0.0f) {
            const Vec3 xi = predicted.get(i);
            const Vec3 omegaI = vorticity.get(i);
            const float magnitudeI = length(omegaI);
            Vec3 eta{};  // gradient of |omega| (SPH difference form)
            for (const std::uint32_t j : search.neighbors(i)) {
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

void resolveSolidCollisions(const SolverConstants& c, const SolidSet& solids, float radius,
                            const Float3Array& position, Float3Array& predicted, std::size_t begin,
                            std::size_t end) {
    const float reach = c.h;
    const float hitDistance = 0.05f * radius;
    for (std::size_t i = begin; i < end; ++i) {
        const Vec3 start = position.get(i);
        Vec3 x = predicted.get(i);
        Vec3 normal;
        const Vec3 move = x - start;
        const float moveLength = length(move);
        // Sweep: sphere-trace from the start; the distance field guarantees no
        // surface closer than d, so each step of length d is safe.
        float startDistance = solids.signedDistance(start, moveLength + reach, normal);
        if (startDistance < moveLength && moveLength > 0.0f) {
            const Vec3 direction = move * (1.0f / moveLength);
            float travelled = std::max(startDistance, 0.0f);
            bool hit = startDistance <= hitDistance;
            for (int step = 0; step < 64 && !hit && travelled < moveLength; ++step) {
                const float d = solids.signedDistance(start + direction * travelled,
                                                      moveLength + reach, normal);
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
        predicted.set(i, clampToBox(c.collisionBox, x));
    }
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
