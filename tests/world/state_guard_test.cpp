// The state guard: a NaN, an infinity or an impossible speed stops the run at
// the step that produced it, names the particle, and no bad frame is written.
#include "pbf/state_guard.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <limits>

#include "pbf/checkpoint.hpp"
#include "pbf/run.hpp"
#include "pbf/simulation.hpp"
#include "support/reliability_util.hpp"

namespace {

namespace fs = std::filesystem;
using pbf::test::freshTestDirectory;
using pbf::test::smallDamBreak;

TEST(StateGuard, NanInjectedIntoAVelocityIsReportedWithTheParticleId) {
    const pbf::test::ThreadCountScope oneThread(1);
    pbf::Simulation simulation(smallDamBreak());
    simulation.advanceFrame();
    pbf::ParticleStore& p = simulation.particles();
    const std::size_t index = p.size() / 3;
    const std::uint32_t id = p.id[index];
    p.velocity.y[index] = std::numeric_limits<float>::quiet_NaN();
    try {
        simulation.advanceFrame();
        FAIL() << "the NaN was not caught";
    } catch (const pbf::StateError& e) {
        EXPECT_EQ(e.particle.id, id);
        EXPECT_EQ(e.frame, 2);
        EXPECT_EQ(e.substep, 0);
        const std::string message = e.what();
        EXPECT_NE(message.find("particle id " + std::to_string(id)), std::string::npos) << message;
        EXPECT_NE(message.find("velocity is not finite"), std::string::npos) << message;
        EXPECT_NE(message.find("frame 2"), std::string::npos) << message;
    }
}

TEST(StateGuard, InfinitePositionIsReported) {
    const pbf::test::ThreadCountScope oneThread(1);
    pbf::Simulation simulation(smallDamBreak());
    simulation.particles().position.x[5] = std::numeric_limits<float>::infinity();
    try {
        simulation.advanceFrame();
        FAIL();
    } catch (const pbf::StateError& e) {
        EXPECT_EQ(e.particle.id, simulation.particles().id[5]);
        EXPECT_NE(std::string(e.what()).find("position is not finite"), std::string::npos);
    }
}

// A limit the falling water crosses during a frame: the check after a solver
// step fires, at a substep > 0, for the first particle over the limit.
TEST(StateGuard, SpeedLimitStopsAfterTheStepThatExceedsIt) {
    const pbf::test::ThreadCountScope oneThread(1);
    pbf::Simulation simulation(smallDamBreak({pbf::parseOverride("output.max_speed=0.3")}));
    EXPECT_DOUBLE_EQ(simulation.speedLimit(), 0.3f);
    try {
        for (int f = 0; f < 30; ++f) simulation.advanceFrame();
        FAIL() << "the speed limit never fired";
    } catch (const pbf::StateError& e) {
        EXPECT_GT(e.substep, 0);
        EXPECT_EQ(e.stage, "after solver step");
        EXPECT_GT(pbf::length(e.particle.velocity), 0.3f);
        EXPECT_NE(std::string(e.what()).find("exceeds the limit of 0.3 m/s"), std::string::npos)
            << e.what();
    }
}

TEST(StateGuard, AutomaticLimitAllowsFreeFallButNotBlowUps) {
    const pbf::test::ThreadCountScope oneThread(1);
    const pbf::Scene scene = smallDamBreak();
    const double limit = pbf::speedLimit(scene);
    // Free fall across the whole domain diagonal (sqrt(1.6^2 + 1 + 0.4^2) m).
    const double freeFall = std::sqrt(2.0 * 9.81 * std::sqrt(1.6 * 1.6 + 1.0 + 0.4 * 0.4));
    EXPECT_NEAR(limit, 10.0 * freeFall, 1e-3 * limit);
    pbf::ParticleStore p = pbf::createParticles(scene);
    EXPECT_FALSE(pbf::findBadParticle(p, limit));
    p.velocity.x[17] = static_cast<float>(1.01 * limit);
    const auto bad = pbf::findBadParticle(p, limit);
    ASSERT_TRUE(bad);
    EXPECT_EQ(bad->index, 17u);
    EXPECT_FALSE(pbf::findBadParticle(p, 0.0));  // speed check off
}

// runScene: frames before the failure are written, none after; the last
// good frame's state is saved as the checkpoint; the message says where.
TEST(StateGuard, RunStopsSavesLastGoodStateAndWritesNoBadFrame) {
    const pbf::test::ThreadCountScope oneThread(1);
    const fs::path dir = freshTestDirectory("guardrun");
    pbf::RunOptions options;
    options.outputDirectory = dir;
    options.frames = 30;
    options.checkpointEvery = 0;
    options.checkpointSeconds = 0.0;
    try {
        pbf::runScene(smallDamBreak({pbf::parseOverride("output.max_speed=0.3")}), options);
        FAIL() << "the run did not stop";
    } catch (const pbf::StateError& e) {
        const int lastGood = e.frame - 1;
        EXPECT_TRUE(fs::exists(dir / pbf::frameFileName(lastGood)));
        EXPECT_FALSE(fs::exists(dir / pbf::frameFileName(e.frame)));
        EXPECT_EQ(pbf::readCheckpoint(dir / pbf::kCheckpointFileName).frame, lastGood);
        EXPECT_NE(
            std::string(e.what()).find("frames up to " + std::to_string(lastGood) + " are good"),
            std::string::npos)
            << e.what();
    }
    fs::remove_all(dir);
}

}  // namespace
