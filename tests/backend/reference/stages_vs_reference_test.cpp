// The SIMD passes of the CPU backend against the reference equations
// (src/backend/reference/equations.hpp) and against the exact value, per
// particle, on random clouds: uniform at about rest density, clustered
// (compressed blobs), at the domain's walls and corners, and around solids.
// The tolerances and their derivation: stage_agreement.hpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <iterator>
#include <ostream>
#include <string>
#include <vector>

#include "backend/cpu/neighbor_search.hpp"
#include "backend/cpu/solver_stages.hpp"
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

    NeighborSearch search(cloud.params.domain, c.h, kMaxGridCells, compactListSpan);
    std::vector<std::uint32_t> perm;
    search.sortByCell(p.predicted, perm);
    p.reorder(perm);
    search.buildNeighborLists(p.predicted);

    const SolidSet* solids = cloud.solids.get();
    std::vector<PackedPoint> predicted(n), withLambda(n), corrected(n), velocityDensity(n);
    out.density.resize(n);
    stages::packPositions(p.predicted, predicted.data(), 0, n);
    inUnevenRanges(n, [&](std::size_t b, std::size_t e) {
        stages::computeDensityAndLambda(c, solids, search, predicted.data(), out.density.data(),
                                        withLambda.data(), b, e);
    });
    inUnevenRanges(n, [&](std::size_t b, std::size_t e) {
        stages::correctPositions(c, solids, nullptr, search, p.position, withLambda.data(),
                                 corrected.data(), b, e);
    });
    // The post-process at the uncorrected x* (any positions do).
    Float3Array velocity;
    velocity.resize(n);
    stages::updateVelocity(1.0f / kDt, p.position, p.predicted, out.density.data(), velocity,
                           velocityDensity.data(), 0, n);
    Float3Array vorticity;
    vorticity.resize(n);
    inUnevenRanges(n, [&](std::size_t b, std::size_t e) {
        stages::applyViscosityAndComputeVorticity(c, cloud.params.fluid.viscosity, search,
                                                  predicted.data(), velocityDensity.data(),
                                                  &vorticity, velocity, b, e);
    });
    for (std::size_t i = 0; i < n; ++i) {
        out.lambda.push_back(withLambda[i].w);
        out.corrected.push_back({corrected[i].x, corrected[i].y, corrected[i].z});
        const PackedPoint& v = velocityDensity[i];
        out.velocity.push_back({v.x, v.y, v.z});
        out.xsphVelocity.push_back(velocity.get(i));
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
