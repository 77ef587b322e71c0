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

// An inlet: a rectangular nozzle fills width x height with floor(w / 2r) x
// floor(h / 2r) sites centred on its axis (level across the stream, upward
// across it), and a flow rate carries that volume per second, each particle
// (2 r)^3 of water.
TEST(Emitter, ARectangularInletCarriesItsFlowRate) {
    const pbf::Scene scene = emitterScene(
        R"({"position": [0.1, 0.5, 0.5], "direction": [1, 0, 0], "width": 0.2, "height": 0.1,
            "flow_rate": 0.004})");
    const std::vector<pbf::Vec3> sites = pbf::emitterDisc(scene.emitters[0], 0.01f);
    ASSERT_EQ(sites.size(), 10u * 5u);
    float lowest = 1.0f, highest = -1.0f, nearest = 1.0f, farthest = -1.0f;
    for (const pbf::Vec3& s : sites) {
        EXPECT_EQ(s.x, 0.0f);  // across the stream
        lowest = std::min(lowest, s.y);
        highest = std::max(highest, s.y);
        nearest = std::min(nearest, s.z);
        farthest = std::max(farthest, s.z);
    }
    EXPECT_NEAR(lowest, -0.04f, 1e-6f);  // 5 rows 2 cm apart about the axis
    EXPECT_NEAR(highest, 0.04f, 1e-6f);
    EXPECT_NEAR(nearest, -0.09f, 1e-6f);  // 10 columns
    EXPECT_NEAR(farthest, 0.09f, 1e-6f);
    pbf::World sim(scene);
    const pbf::Emitter& inlet = sim.emitters()[0];
    // 0.004 m^3/s through 50 sites of (2 cm)^2: 0.2 m/s.
    EXPECT_NEAR(inlet.velocity().x, 0.2f, 1e-6f);
    while (sim.time() < 0.5 - 1e-9) pbf::test::stepFrame(sim);
    const double volume = double(sim.particles().size()) * 0.02 * 0.02 * 0.02;
    EXPECT_NEAR(volume, 0.004 * 0.5, double(inlet.discSize()) * 8e-6);  // within one disc
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
    const auto error = [](const std::string& emitter) {
        try {
            emitterScene(emitter);
        } catch (const pbf::SceneError& e) {
            return std::string(e.what());
        }
        return std::string("accepted");
    };
    EXPECT_NE(error(R"({"position": [0.5, 0.5, 0.5], "width": 0.1, "height": 0.1, "radius": 0.05,
                        "speed": 1})")
                  .find("emitters[0].radius: give either radius or width and height"),
              std::string::npos);
    EXPECT_NE(error(R"({"position": [0.5, 0.5, 0.5], "radius": 0.05, "speed": 1,
                        "flow_rate": 0.001})")
                  .find("emitters[0].speed: give either speed or flow_rate"),
              std::string::npos);
    EXPECT_NE(error(R"({"position": [0.5, 0.5, 0.5], "width": 0.01, "height": 0.1, "speed": 1})")
                  .find("emitters[0].width: must be at least the particle spacing"),
              std::string::npos);
    EXPECT_NE(error(R"({"position": [0.5, 0.5, 0.5], "radius": 0.02, "flow_rate": 1})")
                  .find("emitters[0].flow_rate: the stream would be"),
              std::string::npos);
}

}  // namespace
