#include "backend/reference/stage_agreement.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "backend/boundary.hpp"
#include "backend/reference/equations.hpp"
#include "backend/reference/error_bound.hpp"
#include "backend/reference/neighbor_grid.hpp"
#include "backend/reference/particle_sums.hpp"

namespace pbf::test {
namespace {

constexpr float kDt = kStageDt;
constexpr double kU = kUnitRoundoff;

// ---- Random clouds -----------------------------------------------------------

SimulationParams cloudParams() {
    SimulationParams p;
    p.domain = {{0.0f, 0.0f, 0.0f}, {0.5f, 0.5f, 0.5f}};
    p.particleRadius = 0.01f;
    p.fluid.viscosity = 0.05f;
    p.fluid.vorticity = 0.1f;
    return p;
}

Vec3 uniformIn(std::mt19937& rng, const Aabb& box) {
    std::uniform_real_distribution<float> u01(0.0f, 1.0f);
    const Vec3 e = box.extent();
    return {box.min.x + e.x * u01(rng), box.min.y + e.y * u01(rng), box.min.z + e.z * u01(rng)};
}

void addVelocities(std::mt19937& rng, Cloud& cloud) {
    std::normal_distribution<float> speed(0.0f, 0.5f);
    cloud.velocity.clear();
    for (std::size_t i = 0; i < cloud.predicted.size(); ++i)
        cloud.velocity.push_back({speed(rng), speed(rng), speed(rng)});
}

// n particles at rest density on average: one per spacing^3.
}  // namespace

Cloud uniformCloud(std::size_t n) {
    Cloud cloud{"uniform", cloudParams(), nullptr, {}, {}};
    std::mt19937 rng(1);
    const float side = std::cbrt(float(n)) * cloud.params.particleSpacing();
    const Aabb box{{0.1f, 0.1f, 0.1f}, {0.1f + side, 0.1f + side, 0.1f + side}};
    for (std::size_t i = 0; i < n; ++i) cloud.predicted.push_back(uniformIn(rng, box));
    addVelocities(rng, cloud);
    return cloud;
}

// Dense Gaussian blobs: several times rest density in their cores.
Cloud clusteredCloud(std::size_t n) {
    Cloud cloud{"clustered", cloudParams(), nullptr, {}, {}};
    std::mt19937 rng(2);
    const Vec3 centers[] = {
        {0.15f, 0.2f, 0.2f}, {0.3f, 0.25f, 0.2f}, {0.25f, 0.3f, 0.32f}, {0.35f, 0.15f, 0.3f}};
    std::normal_distribution<float> offset(0.0f, 0.03f);
    for (std::size_t i = 0; i < n; ++i) {
        const Vec3 c = centers[i % 4];
        cloud.predicted.push_back({c.x + offset(rng), c.y + offset(rng), c.z + offset(rng)});
    }
    addVelocities(rng, cloud);
    return cloud;
}

// A cloud in a corner of the domain, touching three walls; a tenth of the
// particles lie exactly on the collision box's faces (as clamped ones do).
Cloud wallCloud(std::size_t n) {
    Cloud cloud{"walls", cloudParams(), nullptr, {}, {}};
    std::mt19937 rng(3);
    const float r = cloud.params.particleRadius;
    const float side = std::cbrt(float(n)) * cloud.params.particleSpacing();
    const Aabb box{{r, r, r}, {r + side, r + 0.8f * side, r + side}};
    for (std::size_t i = 0; i < n; ++i) {
        Vec3 x = uniformIn(rng, box);
        if (i % 10 == 0) x.x = r;
        if (i % 10 == 1) x.y = r;
        if (i % 30 == 2) x = {r, r, x.z};
        cloud.predicted.push_back(x);
    }
    addVelocities(rng, cloud);
    return cloud;
}

// Particles around a sphere and a box, at least one radius outside them.
Cloud solidCloud(std::size_t n) {
    Cloud cloud{"solids", cloudParams(), std::make_unique<SolidSet>(), {}, {}};
    cloud.solids->add(makeSphereSolid({0.2f, 0.2f, 0.25f}, 0.07f));
    cloud.solids->add(makeBoxSolid({{0.28f, 0.12f, 0.18f}, {0.36f, 0.3f, 0.32f}}));
    cloud.solids->setAdhesion(0, 0.5f);  // surface tension's pull (the box has none)
    std::mt19937 rng(4);
    const float r = cloud.params.particleRadius;
    const float side = std::cbrt(float(n)) * cloud.params.particleSpacing();
    const Aabb box{{0.08f, 0.08f, 0.25f - 0.5f * side}, {0.42f, 0.34f, 0.25f + 0.5f * side}};
    while (cloud.predicted.size() < n) {
        const Vec3 x = uniformIn(rng, box);
        Vec3 normal;
        if (cloud.solids->signedDistance(x, 1.0f, normal) >= r) cloud.predicted.push_back(x);
    }
    addVelocities(rng, cloud);
    return cloud;
}

SimulationParams surfaceTensionParams(const Cloud& cloud) {
    SimulationParams params = cloud.params;
    params.fluid.surfaceTension = 0.0728f;
    params.solver.wallAdhesion = kStageWallAdhesion;
    return params;
}

SolverConstants surfaceTensionConstants(const Cloud& cloud) {
    return SolverConstants::from(surfaceTensionParams(cloud));
}

namespace {

// ---- The reference, on the same (reordered) particles ------------------------------

struct ReferenceResults {
    std::vector<float> density, lambda, surfaceLayer;
    std::vector<Vec3> dp, velocity, xsphVelocity, vorticity, surfaceTensionVelocity;
};

// `testedDensity`: the densities the surface layer is found from, and
// `testedLayer` the layer the cohesion is given (both get the same).
ReferenceResults runReference(const Cloud& cloud, const SolverConstants& c,
                              const std::vector<Vec3>& x, const std::vector<Vec3>& xStar,
                              const std::vector<float>& testedDensity,
                              const std::vector<float>& testedLayer) {
    const std::size_t n = xStar.size();
    reference::NeighborGrid grid(cloud.params.domain, c.h);
    grid.build(xStar);
    ReferenceResults r;
    for (std::size_t i = 0; i < n; ++i) {
        const auto dl =
            reference::densityAndLambda(c, cloud.solids.get(), xStar, grid.neighbors(i), i);
        r.density.push_back(dl.density);
        r.lambda.push_back(dl.lambda);
    }
    for (std::size_t i = 0; i < n; ++i) {
        r.dp.push_back(reference::positionCorrection(c, cloud.solids.get(), xStar, r.lambda,
                                                     grid.neighbors(i), i));
        r.velocity.push_back(reference::velocityFromPositions(x[i], xStar[i], kDt));
    }
    for (std::size_t i = 0; i < n; ++i) {
        r.xsphVelocity.push_back(reference::xsphVelocity(
            c, cloud.params.fluid.viscosity, xStar, r.velocity, r.density, grid.neighbors(i), i));
        r.vorticity.push_back(
            reference::vorticity(c, xStar, r.velocity, r.density, grid.neighbors(i), i));
    }
    const SolverConstants cs = surfaceTensionConstants(cloud);
    if (testedLayer.empty()) return r;
    for (std::size_t i = 0; i < n; ++i)
        r.surfaceLayer.push_back(reference::surfaceLayer(cs, cloud.solids.get(), xStar,
                                                         testedDensity[i], grid.neighbors(i), i));
    for (std::size_t i = 0; i < n; ++i) {
        const reference::SurfaceTensionAcceleration a = reference::surfaceTension(
            cs, kStageWallAdhesion, cloud.solids.get(), xStar, testedLayer, grid.neighbors(i), i);
        r.surfaceTensionVelocity.push_back(r.velocity[i] + kDt * a.total);
    }
    return r;
}

// ---- The exact values and their bounds ---------------------------------------------

// The geometry of a pair (i, j), with the bounds of the kernels' arguments.
struct Pair {
    std::uint32_t j = 0;
    double dx[3] = {};  // fl(x_i - x_j): the same float in every implementation
    double r2 = 0.0;
    bool inside = false;     // r^2 < h^2 exactly
    bool ambiguous = false;  // rounding may put it on either side of h
    Bound poly6Shape;        // (h^2 - r^2)^3
    Bound spikyShape;        // (h - r)^2 / r
    Bound inverseR;          // 1 / r
};

struct Model {
    std::vector<std::vector<Pair>> pairs;
    std::vector<Bound> density, lambda, boundaryKernel;
    std::vector<Bound3> dp, velocity, xsphVelocity, vorticity, surfaceTensionVelocity;
    std::vector<Vec3> boundaryGradient;  // shared float (same function, same x)
};

// A pair that one implementation may count and the other not adds its
// whole term to the error.
Bound pairTerm(const Pair& pair, Bound term) {
    if (!pair.ambiguous) return term;
    return {pair.inside ? term.v : 0.0, std::fabs(term.v) + term.e};
}

Model buildModel(const Cloud& cloud, const SolverConstants& c, const std::vector<Vec3>& x,
                 const std::vector<Vec3>& xStar, const std::vector<float>& testedLayer) {
    const std::size_t n = xStar.size();
    const double h = c.h, h2 = c.poly6.h2;
    const double epsRsqrt = 7.0 * kU;
    const double epsInverse = (1.0 + epsRsqrt) * (1.0 + gamma(3)) - 1.0;
    const double epsR = (1.0 + epsInverse) * (1.0 + kU) - 1.0;
    const double m = c.particleMass, gs = double(c.particleMass * c.inverseRestDensity);
    const double c6 = c.poly6.coefficient, cS = c.spiky.gradientCoefficient;
    Model model;
    model.pairs.resize(n);

    // Candidates a little beyond h, so that pairs at the edge are seen.
    reference::NeighborGrid wide(cloud.params.domain, c.h * 1.001f);
    wide.build(xStar);
    for (std::size_t i = 0; i < n; ++i) {
        for (const std::uint32_t j : wide.neighbors(i)) {
            Pair p;
            p.j = j;
            const Vec3 d = xStar[i] - xStar[j];
            p.dx[0] = d.x, p.dx[1] = d.y, p.dx[2] = d.z;
            p.r2 = p.dx[0] * p.dx[0] + p.dx[1] * p.dx[1] + p.dx[2] * p.dx[2];
            p.inside = p.r2 < h2;
            p.ambiguous = std::fabs(p.r2 - h2) <= 4.0 * (epsR + gamma(3)) * h2;
            if (!p.inside && !p.ambiguous) continue;
            const Bound r2{p.r2, gamma(3) * p.r2};
            const Bound d2 = rounded(sub(exact(h2), r2), 1);
            p.poly6Shape = mul(mul(d2, d2), d2);
            p.inverseR = relative(exact(1.0 / std::sqrt(p.r2)), epsInverse);
            const Bound r = relative(exact(std::sqrt(p.r2)), epsR);
            const Bound dh = rounded(sub(exact(h), r), 1);
            p.spikyShape = mul(mul(dh, dh), p.inverseR);
            model.pairs[i].push_back(p);
        }
    }

    // Eq. 2 and 8-11.
    for (std::size_t i = 0; i < n; ++i) {
        float wallKernel = 0.0f;
        Vec3 gradient{};
        boundary::addWallContribution(c, xStar[i], wallKernel, gradient);
        boundary::addSolidContribution(c, cloud.solids.get(), xStar[i], wallKernel, gradient);
        model.boundaryKernel.push_back({double(wallKernel), gamma(6) * wallKernel});
        model.boundaryGradient.push_back(gradient);

        std::vector<Bound> rho, gradSq, grad[3];
        for (const Pair& p : model.pairs[i]) {
            rho.push_back(pairTerm(p, rounded(scale(p.poly6Shape, m * c6), 4)));
            for (int a = 0; a < 3; ++a)
                grad[a].push_back(pairTerm(p, rounded(scale(p.spikyShape, gs * cS * p.dx[a]), 5)));
            // |grad_j C_i|^2 = (gs cS)^2 (h - r)^4 |r_ij|^2 / r^2
            const Bound g = mul(mul(p.spikyShape, p.spikyShape), exact(p.r2));
            gradSq.push_back(pairTerm(p, rounded(scale(g, gs * gs * cS * cS), 13)));
        }
        rho.push_back(rounded(exact(m * c6 * h2 * h2 * h2), 4));
        rho.push_back(rounded(scale(model.boundaryKernel[i], m), 1));
        const Bound density = sum(rho, 6);
        std::vector<Bound> gradISq;
        for (int a = 0; a < 3; ++a) {
            grad[a].push_back(rounded(exact(gs * double(gradient[a])), 1));
            const Bound g = sum(grad[a]);
            gradISq.push_back(rounded(mul(g, g), 1));
        }
        const Bound denominator =
            rounded(add(rounded(add(sum(gradISq), sum(gradSq)), 1), exact(c.relaxationEpsilon)), 1);
        const Bound constraint = positivePart(
            rounded(sub(rounded(scale(density, c.inverseRestDensity), 1), exact(1.0)), 1));
        model.density.push_back(density);
        model.lambda.push_back(rounded(div(scale(constraint, -1.0), denominator), 1));
    }

    // Eq. 12-14 with the lambdas' bounds; v = (x* - x) / dt.
    for (std::size_t i = 0; i < n; ++i) {
        std::vector<Bound> terms[3];
        for (const Pair& p : model.pairs[i]) {
            const Bound ratio = rounded(scale(p.poly6Shape, c6 * c.scorrInverseWdq), 4);
            Bound power = ratio;
            for (int k = 1; k < c.scorrExponent; ++k) power = mul(power, ratio);
            power = rounded(power, c.scorrExponent - 1);
            const Bound scorr = rounded(scale(power, c.scorrScale), 1);
            const Bound lambdaSum = rounded(add(model.lambda[i], model.lambda[p.j]), 1);
            const Bound weight = mul(rounded(add(lambdaSum, scorr), 1), p.spikyShape);
            for (int a = 0; a < 3; ++a)
                terms[a].push_back(pairTerm(p, rounded(scale(weight, gs * cS * p.dx[a]), 6)));
        }
        Bound3 dp, v;
        const Vec3 move = xStar[i] - x[i];
        for (int a = 0; a < 3; ++a) {
            terms[a].push_back(
                rounded(scale(model.lambda[i], gs * double(model.boundaryGradient[i][a])), 2));
            dp[a] = sum(terms[a]);
            const double va = double(move[a]) / double(kDt);
            v[a] = {va, gamma(2) * std::fabs(va)};
        }
        model.dp.push_back(dp);
        model.velocity.push_back(v);
    }

    // Eq. 15 and 17 with the bounds of rho and v.
    const double xsphScale = 2.0 * m * c6 * cloud.params.fluid.viscosity;
    for (std::size_t i = 0; i < n; ++i) {
        std::vector<Bound> xsph[3], omega[3];
        for (const Pair& p : model.pairs[i]) {
            const Bound3& vi = model.velocity[i];
            const Bound3& vj = model.velocity[p.j];
            Bound3 w, g;
            for (int a = 0; a < 3; ++a) w[a] = rounded(sub(vj[a], vi[a]), 1);
            const Bound rhoSum = rounded(add(model.density[i], model.density[p.j]), 1);
            const Bound volumeJ = div(exact(1.0), model.density[p.j]);
            for (int a = 0; a < 3; ++a) {
                xsph[a].push_back(pairTerm(
                    p, rounded(scale(mul(div(p.poly6Shape, rhoSum), w[a]), xsphScale), 7)));
                g[a] = rounded(scale(mul(p.spikyShape, volumeJ), m * cS * p.dx[a]), 7);
            }
            for (int a = 0; a < 3; ++a) {
                const int b = (a + 1) % 3, e = (a + 2) % 3;  // (g x w)_a = g_b w_e - g_e w_b
                omega[a].push_back(pairTerm(
                    p, rounded(sub(rounded(mul(g[b], w[e]), 1), rounded(mul(g[e], w[b]), 1)), 1)));
            }
        }
        Bound3 vNew, om;
        for (int a = 0; a < 3; ++a) {
            vNew[a] = rounded(add(model.velocity[i][a], sum(xsph[a])), 1);
            om[a] = sum(omega[a]);
        }
        model.xsphVelocity.push_back(vNew);
        model.vorticity.push_back(om);
    }

    // Surface tension: the cohesion -S w(r) dx with the same surface flags,
    // w = (s_i + s_j) (h^2 - r^2)^2 for d < r < h and -2 L (r_c - r)^2 / r
    // below r_c (every pair), plus the shared adhesion.
    const SolverConstants cs = surfaceTensionConstants(cloud);
    const double cohesionScale = cs.cohesionScale, d2 = cs.cohesionMinDistance2;
    const double rc2 = cs.cohesionCoreDistance2, rc = cs.cohesionCoreDistance;
    const double coreScale = cs.cohesionCoreScale;
    for (std::size_t i = 0; i < n; ++i) {
        if (testedLayer.empty()) break;
        const int surfaceI = testedLayer[i] > 0.0f ? 1 : 0;
        std::vector<Bound> terms[3];
        for (const Pair& p : model.pairs[i]) {
            const int pairs = surfaceI + (testedLayer[p.j] > 0.0f ? 1 : 0);
            const double edge = 4.0 * (epsR + gamma(3));
            const Bound r2{p.r2, gamma(3) * p.r2};
            // The pull beyond d (a jump there: a pair at the edge adds its whole term).
            const bool beyond = p.r2 > d2;
            const bool atD = std::fabs(p.r2 - d2) <= edge * d2;
            if ((beyond || atD) && pairs > 0) {
                const Bound q = rounded(sub(exact(h2), r2), 1);
                const Bound q2 = mul(q, q);
                for (int a = 0; a < 3; ++a) {
                    Bound t = pairTerm(p, rounded(scale(q2, -cohesionScale * pairs * p.dx[a]), 4));
                    if (atD) t = {beyond ? t.v : 0.0, std::fabs(t.v) + t.e};
                    terms[a].push_back(t);
                }
            }
            // The core below r_c (zero at r_c: no jump).
            const bool inside = p.r2 < rc2;
            const bool atCore = std::fabs(p.r2 - rc2) <= edge * rc2;
            if (inside || atCore) {
                // -2 L (r_c - r)^2 / r, r and 1/r as the spiky kernel's.
                const Bound r = relative(exact(std::sqrt(p.r2)), epsR);
                const Bound gap = rounded(sub(exact(rc), r), 1);
                const Bound w = scale(mul(mul(gap, gap), p.inverseR), -2.0 * coreScale);
                for (int a = 0; a < 3; ++a) {
                    Bound t = rounded(scale(w, -cohesionScale * p.dx[a]), 6);
                    if (atCore) t = {inside ? t.v : 0.0, std::fabs(t.v) + t.e};
                    terms[a].push_back(t);
                }
            }
        }
        const boundary::AdhesionPull pull =
            boundary::adhesionPull(cs, kStageWallAdhesion, cloud.solids.get(), xStar[i]);
        const Vec3 walls = reference::adhesionAcceleration(cs, pull.walls);
        const Vec3 solid = reference::adhesionAcceleration(cs, pull.solid);
        Bound3 vNew;
        for (int a = 0; a < 3; ++a) {
            const Bound cohesion = sum(terms[a]);
            const Bound acceleration =
                rounded(add(rounded(add(cohesion, exact(walls[a])), 1), exact(solid[a])), 1);
            vNew[a] = rounded(add(model.velocity[i][a], rounded(scale(acceleration, kDt), 1)), 1);
        }
        model.surfaceTensionVelocity.push_back(vNew);
    }
    return model;
}

// ---- Comparison ----------------------------------------------------------------

// Worst case over the particles of one quantity.
struct Agreement {
    double usedOfBound = 0.0;  // max |simd - ref| / (bound_simd + bound_ref)
    double largestBound = 0.0;
    double sumOfSquares = 0.0;  // of the exact values
    std::size_t count = 0;
    std::size_t failures = 0;
    std::string firstFailure;

    void check(std::size_t i, const char* what, double simd, double ref, double exactValue,
               double bound, double simdExtra = 0.0, double refExtra = 0.0) {
        const double simdBound = bound + simdExtra, refBound = bound + refExtra;
        const bool ok = std::fabs(simd - exactValue) <= simdBound &&
                        std::fabs(ref - exactValue) <= refBound &&
                        std::fabs(simd - ref) <= simdBound + refBound;
        if (!ok && failures++ == 0) {
            char text[256];
            std::snprintf(text, sizeof text,
                          "%s of particle %zu: tested %.9g, reference %.9g, exact %.9g, bound %.3g",
                          what, i, simd, ref, exactValue, bound);
            firstFailure = text;
        }
        usedOfBound = std::max(usedOfBound, std::fabs(simd - ref) / (simdBound + refBound));
        largestBound = std::max(largestBound, bound);
        sumOfSquares += exactValue * exactValue;
        ++count;
    }
    // The largest bound relative to the quantity's typical size.
    double relativeBound() const {
        return largestBound / std::sqrt(sumOfSquares / double(std::max<std::size_t>(count, 1)));
    }
};

void report(const std::string& cloud, const char* implementation, const char* quantity,
            const Agreement& a) {
    std::printf("  %-9s %-10s |%s - ref| <= %5.1f %% of 2E; max E / rms value %.2e\n",
                cloud.c_str(), quantity, implementation, 100.0 * a.usedOfBound, a.relativeBound());
    EXPECT_EQ(a.failures, 0u) << cloud << ", " << quantity << ": " << a.firstFailure;
}

}  // namespace

void expectAgreementWithReference(const Cloud& cloud, const SolverConstants& c,
                                  const StageResults& results, const char* implementation,
                                  const std::string& label) {
    const StageResults& simd = results;
    const std::size_t n = results.xStar.size();
    const std::vector<Vec3>& x = results.x;
    const std::vector<Vec3>& xStar = results.xStar;
    const ReferenceResults ref =
        runReference(cloud, c, x, xStar, results.density, results.surfaceLayer);
    const Model model = buildModel(cloud, c, x, xStar, results.surfaceLayer);
    const bool withSurfaceTension = !results.surfaceTensionVelocity.empty();

    Agreement density, lambda, dp, velocity, xsph, vorticity, surface;
    std::size_t skippedAtSolids = 0, active = 0;
    for (std::size_t i = 0; i < n; ++i) {
        density.check(i, "rho", simd.density[i], ref.density[i], model.density[i].v,
                      model.density[i].e);
        lambda.check(i, "lambda", simd.lambda[i], ref.lambda[i], model.lambda[i].v,
                     model.lambda[i].e);
        if (model.lambda[i].v < 0.0) ++active;

        // dp as clamp(x* + dp) - x*: the SIMD pass writes only the corrected x*.
        const Vec3 refMoved = boundary::clampToBox(c.collisionBox, xStar[i] + ref.dp[i]);
        if (cloud.solids) {
            // The swept solid collision is not Lipschitz: compare where it
            // leaves x* + dp alone with a margin.
            Vec3 normal;
            const float margin = 1e-5f;
            const float moveLength = length(refMoved - x[i]);
            if (cloud.solids->signedDistance(refMoved, 1.0f, normal) < c.particleRadius + margin ||
                cloud.solids->signedDistance(x[i], 1.0f, normal) < moveLength + margin) {
                ++skippedAtSolids;
                continue;
            }
        }
        for (int a = 0; a < 3; ++a) {
            const double target =
                std::clamp(double(xStar[i][a]) + model.dp[i][a].v, double(c.collisionBox.min[a]),
                           double(c.collisionBox.max[a])) -
                double(xStar[i][a]);
            const double simdDp = double(simd.corrected[i][a]) - double(xStar[i][a]);
            const double refDp = double(refMoved[a]) - double(xStar[i][a]);
            // The addition x* + dp rounds: u |x* + dp| for each.
            dp.check(i, "dp", simdDp, refDp, target, model.dp[i][a].e,
                     kU * std::fabs(simd.corrected[i][a]), kU * std::fabs(refMoved[a]));
        }
    }
    for (std::size_t i = 0; i < n; ++i)
        for (int a = 0; a < 3; ++a) {
            velocity.check(i, "v", simd.velocity[i][a], ref.velocity[i][a], model.velocity[i][a].v,
                           model.velocity[i][a].e);
            xsph.check(i, "xsph v", simd.xsphVelocity[i][a], ref.xsphVelocity[i][a],
                       model.xsphVelocity[i][a].v, model.xsphVelocity[i][a].e);
            vorticity.check(i, "omega", simd.vorticity[i][a], ref.vorticity[i][a],
                            model.vorticity[i][a].v, model.vorticity[i][a].e);
            if (withSurfaceTension)
                surface.check(i, "v + dt a_surface", simd.surfaceTensionVelocity[i][a],
                              ref.surfaceTensionVelocity[i][a],
                              model.surfaceTensionVelocity[i][a].v,
                              model.surfaceTensionVelocity[i][a].e);
        }

    std::printf("  %s, %zu particles, %s: %zu with lambda < 0, %zu skipped at solids\n",
                cloud.name.c_str(), n, label.c_str(), active, skippedAtSolids);
    report(cloud.name, implementation, "density", density);
    report(cloud.name, implementation, "lambda", lambda);
    report(cloud.name, implementation, "dp", dp);
    report(cloud.name, implementation, "velocity", velocity);
    report(cloud.name, implementation, "xsph", xsph);
    report(cloud.name, implementation, "vorticity", vorticity);
    // The clouds exercise what they are meant to.
    EXPECT_GT(active, n / 10) << "too few compressed particles to test lambda and dp";
    if (withSurfaceTension) {
        report(cloud.name, implementation, "surface", surface);
        const SolverConstants cs = surfaceTensionConstants(cloud);
        // The surface layer: the same weights, except for a particle whose
        // spread lies within 1e-3 (relative) of a strand threshold: the
        // sums' order may round it to either side.
        reference::NeighborGrid grid(cloud.params.domain, c.h);
        grid.build(xStar);
        std::size_t strands = 0, differing = 0;
        for (std::size_t i = 0; i < n; ++i) {
            if (reference::onSurface(cs, results.density[i]) && ref.surfaceLayer[i] == 0.0f)
                ++strands;
            if (results.surfaceLayer[i] == ref.surfaceLayer[i]) continue;
            const reference::SpreadAxes axes =
                reference::spreadAxes(cs, xStar, grid.neighbors(i), i);
            const auto near = [](float value, float threshold) {
                return std::fabs(value - threshold) <= 1e-3f * threshold;
            };
            if (!near(axes.middle, cs.strandSpread2) && !near(axes.largest, cs.strandLength2))
                ++differing;
        }
        std::printf("  %-9s surface layer: %zu strand particles, %zu differing\n",
                    cloud.name.c_str(), strands, differing);
        EXPECT_EQ(differing, 0u) << cloud.name << ": surface layer weights differ";
        const auto surfaceParticles =
            std::count_if(results.density.begin(), results.density.end(),
                          [&](float rho) { return reference::onSurface(cs, rho); });
        EXPECT_GT(std::size_t(surfaceParticles), n / 20)
            << "too few surface particles to test cohesion";
        EXPECT_LT(std::size_t(surfaceParticles), n - n / 10)
            << "too few inner particles to test cohesion";
    }
    EXPECT_LT(skippedAtSolids, n / 4);
}

double physicalViscosityDeviation(const Cloud& cloud, const SolverConstants& c, float nu,
                                  const std::vector<Vec3>& xStar, const std::vector<Vec3>& v,
                                  const std::vector<float>& density, const std::vector<Vec3>& after,
                                  float stepDt) {
    const std::size_t n = xStar.size();
    reference::NeighborGrid grid(cloud.params.domain, c.h);
    grid.build(xStar);
    double worst = 0.0;
    std::size_t nearWalls = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const Vec3 a =
            reference::viscosityAcceleration(c, nu, xStar, v, density, grid.neighbors(i), i);
        // The scale: the sum of the terms' magnitudes, normalised as the sum is.
        double magnitude = 0.0, moment = 0.0;
        for (const std::uint32_t j : grid.neighbors(i)) {
            magnitude += length(reference::viscosityTerm(c, nu, xStar[i] - xStar[j], v[i], v[j],
                                                         density[i], density[j]));
            moment +=
                reference::viscosityMomentTerm(c, xStar[i] - xStar[j], density[i], density[j]);
        }
        for (int axis = 0; axis < 3; ++axis)
            for (const int side : {-1, 1})
                nearWalls += reference::wallInReach(c, xStar[i], axis, side) ? 1 : 0;
        const double scale = magnitude * 12.0 / std::max(moment, 6.0) + 1e-12;
        // The stage's result is read back as (v + dt a - v) / dt: both
        // roundings, u |v| each, divided by dt, are allowed on top.
        const double readBack = 4.0 * kU * double(length(after[i])) / double(stepDt);
        const Vec3 stage = (after[i] - v[i]) * (1.0f / stepDt);
        for (int k = 0; k < 3; ++k)
            worst = std::max(
                worst,
                std::max(0.0, std::fabs(double(stage[k]) - double(a[k])) - readBack) / scale);
    }
    std::printf("  %s: largest |stage - reference| / sum |terms| %.2e, %zu wall contacts\n",
                cloud.name.c_str(), worst, nearWalls);
    return worst;
}

double curvatureForceDeviation(const Cloud& cloud, const SolverConstants& c,
                               const std::vector<Vec3>& xStar, const std::vector<Vec3>& a) {
    const std::size_t n = xStar.size();
    reference::NeighborGrid grid(cloud.params.domain, c.h);
    grid.build(xStar);
    std::vector<Vec3> gradient(n), normal(n), ref(n);
    std::vector<float> kappa(n);
    for (std::size_t i = 0; i < n; ++i)
        gradient[i] = reference::colourGradient(c, xStar, grid.neighbors(i), i);
    for (std::size_t i = 0; i < n; ++i)
        normal[i] = reference::bandNormal(c, xStar, gradient, grid.neighbors(i), i);
    for (std::size_t i = 0; i < n; ++i)
        kappa[i] = reference::curvature(c, xStar, gradient, normal, grid.neighbors(i), i);
    for (std::size_t i = 0; i < n; ++i)
        ref[i] = reference::curvatureForceVelocityChange(c, 1.0f, xStar, gradient, kappa,
                                                         grid.neighbors(i), i);
    // The particles whose |g| lies within 1e-4 of the floor may fall on
    // either side of it in another summation order; their band membership
    // reaches three neighbour rings (nb, kappa, then its average).
    std::vector<char> excluded(n, 0);
    std::size_t band = 0, marginal = 0;
    const float reach2 = 9.0f * c.h * c.h;
    for (std::size_t i = 0; i < n; ++i) {
        const float g = length(gradient[i]);
        if (g > c.surfaceFloor) ++band;
        if (!(std::fabs(g - c.surfaceFloor) < 1e-4f * c.surfaceFloor)) continue;
        ++marginal;
        for (std::size_t j = 0; j < n; ++j)
            if (lengthSquared(xStar[i] - xStar[j]) < reach2) excluded[j] = 1;
    }
    double scale2 = 0.0;
    for (std::size_t i = 0; i < n; ++i) scale2 += double(lengthSquared(ref[i]));
    const double scale = std::sqrt(scale2 / double(std::max<std::size_t>(band, 1)));
    double worst = 0.0;
    std::size_t compared = 0;
    for (std::size_t i = 0; i < n; ++i) {
        if (excluded[i]) continue;
        ++compared;
        const double bound = kCurvatureAgreement * (scale + double(length(ref[i]))) + 1e-30;
        for (int axis = 0; axis < 3; ++axis)
            worst = std::max(worst, std::fabs(double(a[i][axis]) - double(ref[i][axis])) / bound);
    }
    std::printf(
        "  %s: largest |stage - reference| / bound %.3f; %zu of %zu particles on the band, %zu "
        "compared (%zu near the floor)\n",
        cloud.name.c_str(), worst, band, n, compared, marginal);
    // The cloud exercises the force: many particles on the band, not all,
    // and nearly all of them compared.
    EXPECT_GT(band, n / 10) << cloud.name;
    EXPECT_LT(band, n) << cloud.name;
    EXPECT_GT(compared, 9 * n / 10) << cloud.name;
    return worst;
}

}  // namespace pbf::test
