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

// The inlet buffer (pbf/core/inlet_buffer.hpp): across the opening, from
// one particle radius behind the nozzle to one kernel radius ahead of it.
TEST(InletBuffer, HoldsTheWaterInFrontOfTheNozzle) {
    const pbf::Scene disc = emitterScene(
        R"({"position": [0.5, 0.9, 0.5], "direction": [0, -1, 0], "radius": 0.05, "speed": 1.0, "end": 0.1})");
    const pbf::World world(disc);
    const pbf::Emitter& e = world.emitters()[0];
    const pbf::InletBuffer b = e.buffer(0.04f);
    EXPECT_EQ(b.velocity, (pbf::Vec3{0.0f, -1.0f, 0.0f}));
    EXPECT_TRUE(b.contains({0.5f, 0.9f, 0.5f}));
    EXPECT_TRUE(b.contains({0.5f, 0.865f, 0.5f + 0.055f}));   // the rim, plus r
    EXPECT_FALSE(b.contains({0.5f, 0.865f, 0.5f + 0.065f}));  // beside it
    EXPECT_TRUE(b.contains({0.5f, 0.905f, 0.5f}));            // r behind
    EXPECT_FALSE(b.contains({0.5f, 0.915f, 0.5f}));
    EXPECT_TRUE(b.contains({0.5f, 0.865f, 0.5f}));  // within the reach ahead
    EXPECT_FALSE(b.contains({0.5f, 0.855f, 0.5f}));
    EXPECT_TRUE(e.open(0.05));
    EXPECT_FALSE(e.open(0.11));

    // A rectangular inlet pouring along +x: 5 x 3 sites of 0.02 m.
    const pbf::Scene inlet = emitterScene(
        R"({"position": [0.1, 0.5, 0.5], "direction": [1, 0, 0], "width": 0.1, "height": 0.06, "speed": 1.0})");
    const pbf::InletBuffer r = pbf::World(inlet).emitters()[0].buffer(0.04f);
    EXPECT_TRUE(r.contains({0.12f, 0.5f + 0.025f, 0.5f + 0.045f}));  // 0.02 + r up, 0.04 + r across
    EXPECT_FALSE(r.contains({0.12f, 0.5f + 0.035f, 0.5f}));          // above it
    EXPECT_FALSE(r.contains({0.12f, 0.5f, 0.5f + 0.055f}));          // beside it
}

// With surface tension the substeps are tens of microseconds, and a disc
// emitted into water that lags by a tenth of a spacing was kicked out at
// 1-2 m/s: without the inlet buffer, 81 of the first 208 particles of this
// nozzle (the dripping nozzle's, 0.2 m/s) flew alone after 1/60 s. With it
// the stream holds together and nothing outruns it.
TEST(InletBuffer, ANozzleWithSurfaceTensionPoursWithoutSpray) {
    const pbf::Scene scene = pbf::parseScene(
        R"({"domain": {"min": [0, 0, 0], "max": [0.02, 0.07, 0.02]}, "particle_radius": 0.00025,
            "fluid": {"surface_tension": 0.0728},
            "solids": [{"type": "cylinder", "base": [0.01, 0.062, 0.01], "axis": [0, 1, 0],
                        "radius": 0.0018, "height": 0.008}],
            "emitters": [{"position": [0.01, 0.0615, 0.01], "direction": [0, -1, 0],
                          "radius": 0.001, "speed": 0.2}],
            "output": {"fps": 60}})",
        "nozzle.json");
    pbf::World world(scene);
    for (int k = 0; k < 2; ++k) pbf::test::stepFrame(world);
    const pbf::ParticleStore& p = world.particles();
    ASSERT_GT(p.size(), 150u);
    const float d = 2.0f * scene.simulation.particleRadius;
    std::size_t alone = 0, fast = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
        bool neighbour = false;
        for (std::size_t j = 0; j < p.size() && !neighbour; ++j)
            neighbour = j != i && pbf::length(p.position.get(i) - p.position.get(j)) < 1.5f * d;
        if (!neighbour) ++alone;
        // 0.2 m/s and 1/30 s of free fall: 0.53 m/s.
        if (pbf::length(p.velocity.get(i)) > 1.0f) ++fast;
    }
    EXPECT_EQ(alone, 0u);
    EXPECT_EQ(fast, 0u);
}

// An inlet under the surface (the open channel's, 6 cm below the pool's
// surface, 0.83 m/s along the channel): each new layer lands inside the
// water ahead, which moves slower than the stream. Without the buffer the
// fastest particle reached 4.1 m/s in the first second (spray); with it
// 1.8 m/s, the water falling over the weir (a 0.17 m drop).
TEST(InletBuffer, ASubmergedInletPoursWithoutSpray) {
    const pbf::Scene scene = pbf::parseScene(
        R"({"domain": {"min": [0, 0, 0], "max": [2.0, 0.4, 0.2]}, "particle_radius": 0.01,
            "fluid_blocks": [{"min": [0.05, 0, 0], "max": [1.0, 0.17, 0.2]}],
            "solids": [{"type": "box", "min": [1.0, 0, 0], "max": [1.06, 0.08, 0.2]}],
            "emitters": [{"position": [0.03, 0.10, 0.1], "direction": [1, 0, 0],
                          "width": 0.2, "height": 0.06, "flow_rate": 0.01}],
            "outlets": [{"type": "plane", "point": [1.9, 0, 0], "normal": [1, 0, 0]}],
            "output": {"fps": 30}})",
        "submerged.json");
    pbf::World world(scene);
    float fastest = 0.0f;
    for (int k = 0; k < 30; ++k) {
        pbf::test::stepFrame(world);
        const pbf::ParticleStore& p = world.particles();
        for (std::size_t i = 0; i < p.size(); ++i)
            fastest = std::max(fastest, pbf::length(p.velocity.get(i)));
    }
    EXPECT_GT(world.emitters()[0].emitted(), 1000u);
    EXPECT_LT(fastest, 3.0f);
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
