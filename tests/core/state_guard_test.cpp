// The state guard: a NaN, an infinity or an impossible speed stops the run at
// the step that produced it, names the particle, and no bad frame is written.
#include "pbf/core/state_guard.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <limits>

#include "pbf/io/checkpoint.hpp"
#include "pbf/run/run.hpp"
#include "pbf/world/world.hpp"
#include "support/reliability_util.hpp"

namespace {

namespace fs = std::filesystem;
using pbf::test::freshTestDirectory;
using pbf::test::smallDamBreak;

// A NaN written into a velocity (through the id-ordered arrays, as a script
// would) fails the next frame before its first step, naming the particle.
TEST(StateGuard, NanInjectedIntoAVelocityIsReportedWithTheParticleId) {
    const pbf::test::ThreadCountScope oneThread(1);
    pbf::World world(smallDamBreak());
    pbf::test::stepFrame(world);
    pbf::ParticleArrays& a = world.arraysById();
    const std::uint32_t id = static_cast<std::uint32_t>(a.count / 3);
    (*a.velocity)[3 * id + 1] = std::numeric_limits<float>::quiet_NaN();
    const pbf::FrameResult result = world.stepFrame();
    ASSERT_FALSE(result.ok()) << "the NaN was not caught";
    const pbf::StepError& e = *result.error;
    EXPECT_EQ(e.kind, pbf::StepError::Kind::BadState);
    ASSERT_TRUE(e.particle);
    EXPECT_EQ(e.particle->id, id);
    EXPECT_EQ(e.frame, 2);
    EXPECT_EQ(e.substep, 0);
    EXPECT_NE(e.message.find("particle id " + std::to_string(id)), std::string::npos) << e.message;
    EXPECT_NE(e.message.find("velocity is not finite"), std::string::npos) << e.message;
    EXPECT_NE(e.message.find("frame 2"), std::string::npos) << e.message;
    EXPECT_EQ(world.frame(), 1);  // the frame did not count
}

TEST(StateGuard, InfinitePositionIsReported) {
    const pbf::test::ThreadCountScope oneThread(1);
    pbf::World world(smallDamBreak());
    (*world.arraysById().position)[3 * 5] = std::numeric_limits<float>::infinity();
    const pbf::FrameResult result = world.stepFrame();
    ASSERT_FALSE(result.ok());
    ASSERT_TRUE(result.error->particle);
    EXPECT_EQ(result.error->particle->id, 5u);
    EXPECT_NE(result.error->message.find("position is not finite"), std::string::npos);
}

// A limit the falling water crosses during a frame: the check after a solver
// step fires, at a substep > 0, for the first particle over the limit.
TEST(StateGuard, SpeedLimitStopsAfterTheStepThatExceedsIt) {
    const pbf::test::ThreadCountScope oneThread(1);
    pbf::World world(smallDamBreak({pbf::parseOverride("guard.max_speed=0.3")}));
    EXPECT_DOUBLE_EQ(world.speedLimit(), 0.3f);
    pbf::FrameResult result;
    for (int f = 0; f < 30 && result.ok(); ++f) result = world.stepFrame();
    ASSERT_FALSE(result.ok()) << "the speed limit never fired";
    const pbf::StepError& e = *result.error;
    EXPECT_GT(e.substep, 0);
    EXPECT_EQ(e.stage, "after solver step");
    ASSERT_TRUE(e.particle);
    EXPECT_GT(pbf::length(e.particle->velocity), 0.3f);
    EXPECT_NE(e.message.find("exceeds the limit of 0.3 m/s (guard.max_speed)"), std::string::npos)
        << e.message;
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

// runScene: frames before the failure are written, none after; the run
// returns the error (no exception), its message names the last checkpoint,
// and resuming from it with a higher limit finishes the run.
TEST(StateGuard, RunStopsWritesNoBadFrameAndCanBeResumedFromTheLastCheckpoint) {
    const pbf::test::ThreadCountScope oneThread(1);
    const fs::path dir = freshTestDirectory("guardrun");
    const pbf::Scene limited = pbf::test::withOutput(
        smallDamBreak({pbf::parseOverride("guard.max_speed=1.5")}), dir, 30, 2);
    const pbf::RunSummary s = pbf::runScene(limited, {});
    ASSERT_TRUE(s.error) << "the run did not stop";
    const int lastGood = s.error->frame - 1;
    EXPECT_EQ(s.frames, lastGood);
    EXPECT_TRUE(fs::exists(dir / pbf::frameFileName(lastGood)));
    EXPECT_FALSE(fs::exists(dir / pbf::frameFileName(s.error->frame)));
    const int checkpointFrame = pbf::readCheckpoint(dir / pbf::kCheckpointFileName).frame;
    EXPECT_LE(checkpointFrame, lastGood);
    EXPECT_GT(checkpointFrame, lastGood - 2);  // one every 2 frames
    EXPECT_NE(s.error->message.find("frames up to " + std::to_string(lastGood) + " are written"),
              std::string::npos)
        << s.error->message;
    EXPECT_NE(s.error->message.find("checkpoint of frame " + std::to_string(checkpointFrame)),
              std::string::npos)
        << s.error->message;
    // summary.json records why the run stopped.
    EXPECT_NE(pbf::test::fileBytes(dir / "summary.json").find("exceeds the limit"),
              std::string::npos);
    // The guard is not part of the scene's fingerprint: raise it and resume.
    pbf::RunOptions resume;
    resume.resume = true;
    const pbf::RunSummary resumed = pbf::runScene(
        pbf::test::withOutput(smallDamBreak({pbf::parseOverride("guard.max_speed=50")}), dir, 12),
        resume);
    EXPECT_FALSE(resumed.error);
    EXPECT_EQ(resumed.resumedFromFrame, checkpointFrame);
    EXPECT_TRUE(fs::exists(dir / pbf::frameFileName(12)));
    fs::remove_all(dir);
}

}  // namespace
