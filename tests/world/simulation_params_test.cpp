// Simulation::setParams: live parameter changes between frames (the viewer's panel).
#include <gtest/gtest.h>

#include "pbf/scene.hpp"
#include "pbf/simulation.hpp"
#include "support/test_util.hpp"

namespace {

TEST(SimulationParams, SetParamsTakesEffectOnTheNextFrame) {
    const pbf::Scene scene = pbf::parseScene(pbf::test::smallSceneJson(), "small");
    pbf::Simulation simulation(scene);
    pbf::SimulationParams params = scene.simulation;
    params.solver.iterations = 9;
    params.fluid.viscosity = 0.05f;
    simulation.setParams(params);
    EXPECT_EQ(simulation.solver().params().solver.iterations, 9);
    EXPECT_EQ(simulation.scene().simulation.fluid.viscosity, 0.05f);
    EXPECT_EQ(simulation.advanceFrame().iterations, 9);
}

TEST(SimulationParams, SetParamsRefusesInvalidOrStructuralChanges) {
    const pbf::Scene scene = pbf::parseScene(pbf::test::smallSceneJson(), "small");
    pbf::Simulation simulation(scene);
    pbf::SimulationParams bad = scene.simulation;
    bad.solver.iterations = 0;
    try {
        simulation.setParams(bad);
        FAIL() << "iterations 0 accepted";
    } catch (const pbf::SceneError& e) {
        EXPECT_NE(std::string(e.what()).find("solver.iterations"), std::string::npos) << e.what();
    }
    pbf::SimulationParams radius = scene.simulation;
    radius.particleRadius *= 2.0f;
    EXPECT_THROW(simulation.setParams(radius), pbf::SceneError);
    // Nothing changed.
    EXPECT_EQ(simulation.solver().params().solver.iterations, scene.simulation.solver.iterations);
    EXPECT_EQ(simulation.scene().simulation.particleRadius, scene.simulation.particleRadius);
}

}  // namespace
