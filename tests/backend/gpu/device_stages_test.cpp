// The GPU backend's kernels, one stage at a time, against the reference
// equations and the exact values within the derived float error bounds the
// SIMD passes are held to (tests/backend/reference/stage_agreement.hpp), on
// the same random clouds: uniform, clustered, at walls and around solids.
// Run on the device under test (device_test_util.hpp: cuda-on-cpu, or a GPU).
//
// What it catches: any kernel computing another quantity than the
// reference's (a term dropped or doubled moves lambda or dp far outside
// bounds of ~1e-6 relative), neighbours missed or counted twice by the
// stencil walk over the sorted grid, a reorder that mixes up particles'
// fields (x and x* of different particles: v and dp wrong), the device's
// solids (the shapes and poses in device memory) disagreeing with the
// host's; surface tension's kernel (cohesion, the walls' and the solids'
// adhesion: a device solid's adhesion not uploaded leaves the solid cloud's
// sphere without its pull, far outside the bounds) and the physical
// viscosity's (a wall mirror or a neighbour dropped).
#include <gtest/gtest.h>

#include <ostream>
#include <string>
#include <vector>

#include "backend/gpu/device_test_util.hpp"
#include "backend/reference/stage_agreement.hpp"

namespace pbf::test {
namespace {

struct Case {
    const char* name;
    Cloud (*make)(std::size_t);
    std::size_t count;
};

void PrintTo(const Case& testCase, std::ostream* out) {
    *out << testCase.name << ", " << testCase.count << " particles";
}

class DeviceVsReference : public ::testing::TestWithParam<Case> {};

// The cloud's start-of-step positions x = x* - dt v (the stages' input).
std::vector<Vec3> startPositions(const Cloud& cloud) {
    std::vector<Vec3> x;
    for (std::size_t i = 0; i < cloud.predicted.size(); ++i)
        x.push_back(cloud.predicted[i] - kStageDt * cloud.velocity[i]);
    return x;
}

// Every device stage of one step on the cloud, surface tension on.
gpu::StageOutputs runCloudStages(const Cloud& cloud, const std::vector<Vec3>& x) {
    const SimulationParams surfaceTension = surfaceTensionParams(cloud);
    return runDeviceStages(cloud.params, cloud.solids.get(), x, cloud.predicted, kStageDt,
                           &surfaceTension);
}

TEST_P(DeviceVsReference, AgreeWithinTheDerivedBounds) {
    PBF_REQUIRE_DEVICE();
    const Case& param = GetParam();
    const Cloud cloud = param.make(param.count);
    const SolverConstants c = SolverConstants::from(cloud.params);
    const std::vector<Vec3> x = startPositions(cloud);
    const gpu::StageOutputs out = runCloudStages(cloud, x);
    ASSERT_EQ(out.input.size(), x.size());
    // Every particle once, with its own x and x* (the reorder kept them together).
    std::vector<int> seen(x.size(), 0);
    for (std::size_t i = 0; i < out.input.size(); ++i) {
        ASSERT_LT(out.input[i], x.size());
        ++seen[out.input[i]];
        ASSERT_EQ(out.x[i], x[out.input[i]]) << "particle " << i;
        ASSERT_EQ(out.xStar[i], cloud.predicted[out.input[i]]) << "particle " << i;
    }
    for (const int s : seen) ASSERT_EQ(s, 1);

    StageResults results;
    results.x = out.x;
    results.xStar = out.xStar;
    results.density = out.density;
    results.lambda = out.lambda;
    results.corrected = out.corrected;
    results.velocity = out.velocity;
    results.xsphVelocity = out.xsphVelocity;
    results.vorticity = out.vorticity;
    results.surfaceTensionVelocity = out.surfaceTensionVelocity;
    results.surfaceLayer = out.surfaceLayer;
    ASSERT_EQ(results.surfaceTensionVelocity.size(), x.size());
    EXPECT_TRUE(out.viscosityVelocity.empty());  // fluid.kinematic_viscosity is off
    expectAgreementWithReference(cloud, c, results, "device",
                                 std::string(backendName(deviceUnderTest())));
}

// The physical viscosity's kernel against the reference's sum
// (stage_agreement.hpp: physicalViscosityDeviation), on the device's own
// v = (x* - x) / dt and densities, with a step of 1 s.
TEST_P(DeviceVsReference, PhysicalViscosityStageMatchesTheReference) {
    PBF_REQUIRE_DEVICE();
    const Case& param = GetParam();
    Cloud cloud = param.make(param.count);
    const float nu = 1e-3f;
    cloud.params.fluid.kinematicViscosity = nu;
    const SolverConstants c = SolverConstants::from(cloud.params);
    const std::vector<Vec3> x = startPositions(cloud);
    const gpu::StageOutputs out =
        runDeviceStages(cloud.params, cloud.solids.get(), x, cloud.predicted, kStageDt);
    ASSERT_EQ(out.viscosityVelocity.size(), x.size());
    EXPECT_TRUE(out.surfaceTensionVelocity.empty());
    EXPECT_LT(physicalViscosityDeviation(cloud, c, nu, out.xStar, out.velocity, out.density,
                                         out.viscosityVelocity, 1.0f),
              kViscosityAgreement);
}

// The curvature force's four kernels (g, nb, kappa, then the force)
// against the reference's sums within stage_agreement.hpp's agreement
// (curvatureForceDeviation), with surface tension's constants.
TEST_P(DeviceVsReference, CurvatureForceKernelsMatchTheReference) {
    PBF_REQUIRE_DEVICE();
    const Case& param = GetParam();
    const Cloud cloud = param.make(param.count);
    const SolverConstants cs = surfaceTensionConstants(cloud);
    const std::vector<Vec3> x = startPositions(cloud);
    const gpu::StageOutputs out = runCloudStages(cloud, x);
    ASSERT_EQ(out.curvatureAcceleration.size(), x.size());
    EXPECT_LE(curvatureForceDeviation(cloud, cs, out.xStar, out.curvatureAcceleration), 1.0);
}

INSTANTIATE_TEST_SUITE_P(Clouds, DeviceVsReference,
                         ::testing::Values(Case{"Uniform", &uniformCloud, 3001},
                                           Case{"Clustered", &clusteredCloud, 4099},
                                           Case{"Walls", &wallCloud, 3500},
                                           Case{"Solids", &solidCloud, 3333}),
                         [](const ::testing::TestParamInfo<Case>& caseInfo) {
                             return std::string(caseInfo.param.name);
                         });

}  // namespace
}  // namespace pbf::test
