// The SIMD passes of the CPU backend against the reference equations
// (src/backend/reference/equations.hpp) and against the exact value, per
// particle, on random clouds: uniform at about rest density, clustered
// (compressed blobs), at the domain's walls and corners, and around solids.
// The tolerances and their derivation: stage_agreement.hpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <ostream>
#include <random>
#include <string>
#include <vector>

#include "backend/cpu/neighbor_search.hpp"
#include "backend/cpu/solver_stages.hpp"
#include "backend/reference/equations.hpp"
#include "backend/reference/error_bound.hpp"
#include "backend/reference/neighbor_grid.hpp"
#include "backend/reference/particle_sums.hpp"
#include "backend/reference/stage_agreement.hpp"
#include "pbf/core/solver_constants.hpp"
#include "pbf/geometry/solids.hpp"

namespace pbf::test {
namespace {

constexpr float kDt = kStageDt;

// Calls a stage over [0, n) in ranges that do not follow the 1024-particle
// list blocks (the stages split them at block boundaries themselves).
template <class Fn>
void inUnevenRanges(std::size_t n, Fn&& fn) {
    const std::size_t cuts[] = {0, 700, 2100, 2200, n};
    for (std::size_t k = 0; k + 1 < std::size(cuts); ++k) {
        const std::size_t begin = std::min(cuts[k], n), end = std::min(cuts[k + 1], n);
        if (begin < end) fn(begin, end);
    }
}

StageResults runSimdStages(const Cloud& cloud, const SolverConstants& c,
                           std::uint32_t compactListSpan) {
    StageResults out;
    ParticleStore p;
    const std::size_t n = cloud.predicted.size();
    for (std::size_t i = 0; i < n; ++i)
        p.add(cloud.predicted[i] - kDt * cloud.velocity[i], {}, c.restDensity);
    for (std::size_t i = 0; i < n; ++i) p.predicted.set(i, cloud.predicted[i]);

    NeighborSearch search(cloud.params.domain, c.h, compactListSpan);
    std::vector<std::uint32_t> perm;
    search.sortByCell(p.predicted, perm);
    p.reorder(perm);
    search.buildNeighborLists(p.predicted);

    // The stages read their inputs from a step context over this store and
    // search, with the test's buffers in it.
    const SolverContext context{cloud.params, c, cloud.solids.get()};
    SolverStep s(context, search, p, kDt, nullptr);
    std::vector<PackedPoint> predicted(n), withLambda(n), corrected(n), velocityDensity(n);
    s.predicted = predicted.data();
    s.withLambda = withLambda.data();
    s.velocityDensity = velocityDensity.data();
    stages::packPositions(s, 0, n);
    inUnevenRanges(n,
                   [&](std::size_t b, std::size_t e) { stages::computeDensityAndLambda(s, b, e); });
    out.density = p.density;
    s.predicted = corrected.data();  // the correction's output
    inUnevenRanges(n, [&](std::size_t b, std::size_t e) { stages::correctPositions(s, b, e); });
    s.predicted = predicted.data();
    // The post-process at the uncorrected x* (any positions do).
    stages::updateVelocity(s, 0, n);
    Float3Array vorticity;
    vorticity.resize(n);
    s.vorticity = &vorticity;
    s.terms.vorticity = true;  // omega_i whatever the cloud's settings
    inUnevenRanges(n, [&](std::size_t b, std::size_t e) {
        stages::applyViscosityAndComputeVorticity(s, b, e);
    });
    for (std::size_t i = 0; i < n; ++i) out.xsphVelocity.push_back(p.velocity.get(i));
    // Surface tension at the uncorrected x*, from v = (x* - x) / dt, with the
    // density pass's densities (the reference gets the same ones).
    {
        const SimulationParams stParams = surfaceTensionParams(cloud);
        const SolverConstants cs = surfaceTensionConstants(cloud);
        const SolverContext stContext{stParams, cs, cloud.solids.get()};
        SolverStep st(stContext, search, p, kDt, nullptr);
        std::vector<PackedPoint> positionLayer(n);
        std::vector<float> layer(n);
        st.predicted = predicted.data();
        st.positionLayer = positionLayer.data();
        st.surfaceLayer = layer.data();
        for (std::size_t i = 0; i < n; ++i)
            p.velocity.set(i, {velocityDensity[i].x, velocityDensity[i].y, velocityDensity[i].z});
        inUnevenRanges(
            n, [&](std::size_t b, std::size_t e) { stages::computeSurfaceLayer(st, b, e); });
        out.surfaceLayer = layer;
        stages::packPositionLayers(st, 0, n);
        inUnevenRanges(
            n, [&](std::size_t b, std::size_t e) { stages::applySurfaceTension(st, b, e); });
        for (std::size_t i = 0; i < n; ++i) out.surfaceTensionVelocity.push_back(p.velocity.get(i));
    }
    for (std::size_t i = 0; i < n; ++i) {
        out.lambda.push_back(withLambda[i].w);
        out.corrected.push_back({corrected[i].x, corrected[i].y, corrected[i].z});
        const PackedPoint& v = velocityDensity[i];
        out.velocity.push_back({v.x, v.y, v.z});
        out.vorticity.push_back(vorticity.get(i));
        out.x.push_back(p.position.get(i));
        out.xStar.push_back(p.predicted.get(i));
    }
    return out;
}

struct Case {
    const char* name;
    Cloud (*make)(std::size_t);
    std::size_t count;  // not a multiple of the 1024-particle list blocks
    std::uint32_t compactListSpan;
};

// Names the case in test listings (ctest) instead of dumping its bytes.
void PrintTo(const Case& testCase, std::ostream* out) {
    *out << testCase.name << ", " << testCase.count << " particles";
}

class SimdVsReference : public ::testing::TestWithParam<Case> {};

TEST_P(SimdVsReference, AgreeWithinTheDerivedBounds) {
    const Case& param = GetParam();
    const Cloud cloud = param.make(param.count);
    const SolverConstants c = SolverConstants::from(cloud.params);
    const StageResults simd = runSimdStages(cloud, c, param.compactListSpan);
    expectAgreementWithReference(cloud, c, simd, "simd",
                                 param.compactListSpan ? "compact lists" : "wide lists");
}

// The physical viscosity (fluid.kinematic_viscosity): the CPU stage against
// the reference's sum (stage_agreement.hpp: physicalViscosityDeviation).
TEST_P(SimdVsReference, PhysicalViscosityStageMatchesTheReference) {
    const Case& param = GetParam();
    Cloud cloud = param.make(param.count);
    const float nu = 1e-3f;
    cloud.params.fluid.kinematicViscosity = nu;
    const SolverConstants c = SolverConstants::from(cloud.params);
    const std::size_t n = cloud.predicted.size();
    ParticleStore p;
    for (std::size_t i = 0; i < n; ++i)
        p.add(cloud.predicted[i] - kDt * cloud.velocity[i], {}, c.restDensity);
    for (std::size_t i = 0; i < n; ++i) p.predicted.set(i, cloud.predicted[i]);
    NeighborSearch search(cloud.params.domain, c.h, param.compactListSpan);
    std::vector<std::uint32_t> perm;
    search.sortByCell(p.predicted, perm);
    p.reorder(perm);
    search.buildNeighborLists(p.predicted);
    std::vector<PackedPoint> predicted(n), velocityDensity(n);
    std::vector<float> density(n);
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> jitter(0.98f, 1.02f);
    for (float& d : density) d = c.restDensity * jitter(rng);
    std::copy(density.begin(), density.end(), p.density.begin());
    const SolverContext context{cloud.params, c, nullptr};
    SolverStep s(context, search, p, kDt, nullptr);
    s.predicted = predicted.data();
    s.velocityDensity = velocityDensity.data();
    stages::packPositions(s, 0, n);
    stages::updateVelocity(s, 0, n);
    // The stage adds dt a to v: a step of 1 s makes a large beside v, so
    // that reading it back loses little (the step's length is only a factor).
    const float kViscosityDt = 1.0f;
    s.dt = kViscosityDt;
    const Float3Array before = p.velocity;
    inUnevenRanges(n,
                   [&](std::size_t b, std::size_t e) { stages::applyPhysicalViscosity(s, b, e); });
    std::vector<Vec3> xStar(n), v(n), after(n);
    for (std::size_t i = 0; i < n; ++i) {
        xStar[i] = p.predicted.get(i);
        v[i] = before.get(i);
        after[i] = p.velocity.get(i);
    }
    EXPECT_LT(physicalViscosityDeviation(cloud, c, nu, xStar, v, density, after, kViscosityDt),
              kViscosityAgreement);
}

// The curvature force: the CPU's four passes (g, nb, kappa, then the
// force) against the reference's sums within stage_agreement.hpp's
// agreement (curvatureForceDeviation). Catches a pass dropped or run out of
// order, a field read from the wrong pass, a wrong sign or scale, or a pass
// that read another particle's neighbours.
TEST_P(SimdVsReference, CurvatureForceStagesMatchTheReference) {
    const Case& param = GetParam();
    const Cloud cloud = param.make(param.count);
    const SolverConstants c = surfaceTensionConstants(cloud);
    ASSERT_GT(c.surfaceTension, 0.0f);
    const std::size_t n = cloud.predicted.size();
    ParticleStore p;
    for (std::size_t i = 0; i < n; ++i) p.add(cloud.predicted[i], {}, c.restDensity);
    NeighborSearch search(cloud.params.domain, c.h, param.compactListSpan);
    std::vector<std::uint32_t> perm;
    search.sortByCell(p.predicted, perm);
    p.reorder(perm);
    search.buildNeighborLists(p.predicted);
    // v = 0 (the store's) and a step of 1 s: the last stage leaves a itself in v.
    const SimulationParams params = surfaceTensionParams(cloud);
    const SolverContext context{params, c, nullptr};
    SolverStep s(context, search, p, 1.0f, nullptr);
    std::vector<PackedPoint> predicted(n);
    Float3Array gradient, normal;
    gradient.resize(n);
    normal.resize(n);
    std::vector<float> kappa(n);
    s.predicted = predicted.data();
    s.colourGradient = &gradient;
    s.bandNormal = &normal;
    s.curvature = kappa.data();
    stages::packPositions(s, 0, n);
    inUnevenRanges(n,
                   [&](std::size_t b, std::size_t e) { stages::computeColourGradient(s, b, e); });
    inUnevenRanges(n, [&](std::size_t b, std::size_t e) { stages::computeBandNormal(s, b, e); });
    inUnevenRanges(n, [&](std::size_t b, std::size_t e) { stages::computeCurvature(s, b, e); });
    inUnevenRanges(n, [&](std::size_t b, std::size_t e) { stages::applyCurvatureForce(s, b, e); });
    std::vector<Vec3> xStar(n), a(n);
    for (std::size_t i = 0; i < n; ++i) {
        xStar[i] = p.predicted.get(i);
        a[i] = p.velocity.get(i);
    }
    EXPECT_LE(curvatureForceDeviation(cloud, c, xStar, a), 1.0);
}

INSTANTIATE_TEST_SUITE_P(Clouds, SimdVsReference,
                         ::testing::Values(Case{"UniformCompact", &uniformCloud, 3001, 65536},
                                           Case{"UniformWide", &uniformCloud, 3001, 0},
                                           Case{"ClusteredCompact", &clusteredCloud, 4099, 65536},
                                           Case{"ClusteredWide", &clusteredCloud, 4099, 0},
                                           Case{"WallsCompact", &wallCloud, 3500, 65536},
                                           Case{"WallsWide", &wallCloud, 3500, 0},
                                           Case{"SolidsCompact", &solidCloud, 3333, 65536},
                                           Case{"SolidsWide", &solidCloud, 3333, 0}),
                         [](const ::testing::TestParamInfo<Case>& caseInfo) {
                             return std::string(caseInfo.param.name);
                         });

}  // namespace
}  // namespace pbf::test
