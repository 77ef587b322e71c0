// Emitters: the particle count follows the configured rate.
#include "pbf/world/emitter.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "pbf/io/scene.hpp"
#include "pbf/world/world.hpp"
#include "support/test_util.hpp"

namespace {

pbf::Scene emitterScene(const std::string& emitter) {
    return pbf::parseScene(R"({"domain": {"min": [0,0,0], "max": [1,1,1]}, "particle_radius": 0.01,
      "gravity": [0, 0, 0], "output": {"fps": 50, "frames": 25}, "emitters": [)" +
                               emitter + "]}",
                           "emit.json");
}

TEST(Emitter, CountFollowsTheRate) {
    const pbf::Scene scene = emitterScene(
        R"({"position": [0.5, 0.9, 0.5], "direction": [0, -1, 0], "radius": 0.05, "speed": 1.0, "start": 0.1, "end": 0.4})");
    pbf::World sim(scene);
    ASSERT_EQ(sim.emitters().size(), 1u);
    const pbf::Emitter& emitter = sim.emitters()[0];
    const double interval = 0.02 / 1.0;  // one disc per spacing travelled
    while (sim.time() < 0.5 - 1e-9) {
        pbf::test::stepFrame(sim);
        const double active = std::clamp(sim.time() - 0.1, 0.0, 0.3);
        const double expected = emitter.rate() * active;
        // Within one disc (the particles of one emission interval).
        EXPECT_NEAR(double(sim.particles().size()), expected,
                    double(emitter.discSize()) * (1.0 + 1e-5))
            << "t = " << sim.time();
    }
    EXPECT_NEAR(emitter.rate(), double(emitter.discSize()) / interval, 1e-5 * emitter.rate());
    EXPECT_GT(emitter.discSize(), 20u);  // pi (0.05 / 0.02)^2 ~ 20 sites
    // The stream stays a stream: apart from its tip (the first disc, pushed
    // ahead by the artificial pressure of the disc behind it) nothing is
    // faster than it was emitted.
    std::size_t fast = 0;
    for (std::size_t i = 0; i < sim.particles().size(); ++i)
        if (pbf::length(sim.particles().velocity.get(i)) > 1.2f) ++fast;
    EXPECT_LE(fast, 2 * emitter.discSize());
}

TEST(Emitter, BudgetIsRespected) {
    const pbf::Scene scene = emitterScene(
        R"({"position": [0.5, 0.9, 0.5], "direction": [0, -1, 0], "radius": 0.05, "speed": 2.0, "max_particles": 100})");
    pbf::World sim(scene);
    while (sim.time() < 0.3) pbf::test::stepFrame(sim);
    EXPECT_EQ(sim.particles().size(), 100u);
}

TEST(Emitter, BadEmittersAreRefused) {
    EXPECT_THROW(emitterScene(R"({"position": [5, 0.9, 0.5], "radius": 0.05, "speed": 1})"),
                 pbf::SceneError);
    EXPECT_THROW(emitterScene(R"({"position": [0.5, 0.9, 0.5], "radius": 0.05, "speed": -1})"),
                 pbf::SceneError);
    EXPECT_THROW(
        emitterScene(
            R"({"position": [0.5, 0.9, 0.5], "direction": [0,0,0], "radius": 0.05, "speed": 1})"),
        pbf::SceneError);
    EXPECT_THROW(
        emitterScene(
            R"({"position": [0.5, 0.9, 0.5], "radius": 0.05, "speed": 1, "start": 2, "end": 1})"),
        pbf::SceneError);
}

}  // namespace
