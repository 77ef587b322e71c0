// The step's optional terms (src/backend/step_terms.hpp): each setting
// switches its own term and no other, so that every backend, which reads
// only these flags, runs a term under the same condition.
#include <gtest/gtest.h>

#include "backend/step_terms.hpp"

namespace pbf::test {
namespace {

SimulationParams allOff() {
    SimulationParams params;
    params.fluid.viscosity = 0.0f;
    params.fluid.vorticity = 0.0f;
    params.fluid.kinematicViscosity = 0.0f;
    params.fluid.surfaceTension = 0.0f;
    params.solver.warmStart = 0.0f;
    params.solver.maxDensityError = 0.0f;
    return params;
}

StepTerms termsOf(const SimulationParams& params) {
    return stepTerms(params, SolverConstants::from(params), false);
}

int termsOn(const StepTerms& t) {
    return int(t.warmStart) + int(t.xsph) + int(t.vorticity) + int(t.physicalViscosity) +
           int(t.cohesion) + int(t.curvature) + int(t.solids) + int(t.errorControlled);
}

TEST(StepTerms, AllOffWithoutTheirSettings) {
    const StepTerms t = termsOf(allOff());
    EXPECT_EQ(termsOn(t), 0);
    EXPECT_FALSE(t.viscosityPass());
    EXPECT_FALSE(t.velocityPostProcess());
}

TEST(StepTerms, EachSettingSwitchesItsTerm) {
    SimulationParams params = allOff();
    params.solver.warmStart = 0.8f;
    EXPECT_TRUE(termsOf(params).warmStart);
    EXPECT_EQ(termsOn(termsOf(params)), 1);

    params = allOff();
    params.fluid.viscosity = 0.01f;
    StepTerms t = termsOf(params);
    EXPECT_TRUE(t.xsph && t.viscosityPass() && t.velocityPostProcess());
    EXPECT_EQ(termsOn(t), 1);

    params = allOff();
    params.fluid.vorticity = 0.01f;
    t = termsOf(params);
    EXPECT_TRUE(t.vorticity && t.viscosityPass() && t.velocityPostProcess());
    EXPECT_EQ(termsOn(t), 1);

    params = allOff();
    params.fluid.kinematicViscosity = 1e-3f;
    t = termsOf(params);
    EXPECT_TRUE(t.physicalViscosity && t.velocityPostProcess());
    EXPECT_FALSE(t.viscosityPass());
    EXPECT_EQ(termsOn(t), 1);

    // Surface tension: its cohesion and its curvature force together.
    params = allOff();
    params.fluid.surfaceTension = 0.0728f;
    t = termsOf(params);
    EXPECT_TRUE(t.cohesion && t.curvature);
    EXPECT_EQ(termsOn(t), 2);

    params = allOff();
    params.solver.maxDensityError = 0.001f;
    EXPECT_TRUE(termsOf(params).errorControlled);
    EXPECT_EQ(termsOn(termsOf(params)), 1);
}

TEST(StepTerms, SolidsOnlyWhenThereAreAny) {
    const SimulationParams params = allOff();
    const SolverConstants constants = SolverConstants::from(params);
    SolidSet solids;
    EXPECT_FALSE(stepTerms({params, constants, nullptr}).solids);
    EXPECT_FALSE(stepTerms({params, constants, &solids}).solids);
    EXPECT_EQ(presentSolids(&solids), nullptr);
    solids.add(makeBoxSolid({{0.1f, 0.1f, 0.1f}, {0.3f, 0.3f, 0.3f}}));
    EXPECT_TRUE(stepTerms({params, constants, &solids}).solids);
    EXPECT_EQ(presentSolids(&solids), &solids);
}

// A plan's enabled test reads the step context's terms.
TEST(StepTerms, WhenOnReadsTheContextsTerms) {
    struct Context {
        StepTerms terms;
    } context;
    const auto vorticity = whenOn(&StepTerms::vorticity);
    const auto pass = whenOn(&StepTerms::viscosityPass);
    EXPECT_FALSE(vorticity(context));
    EXPECT_FALSE(pass(context));
    context.terms.vorticity = true;
    EXPECT_TRUE(vorticity(context));
    EXPECT_TRUE(pass(context));
}

}  // namespace
}  // namespace pbf::test
