// Checkpoints: a run resumed from a checkpoint writes the same bytes as one
// that was never interrupted; damaged or foreign checkpoints are refused.
#include "pbf/io/checkpoint.hpp"

#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "pbf/io/io.hpp"
#include "pbf/run/run.hpp"
#include "pbf/world/world.hpp"
#include "support/reliability_util.hpp"

namespace {

namespace fs = std::filesystem;
using pbf::test::fileBytes;
using pbf::test::freshTestDirectory;
using pbf::test::smallDamBreak;

constexpr int kFrames = 7;

using pbf::test::withOutput;

void expectSameFrames(const fs::path& a, const fs::path& b, int first, int last) {
    for (int f = first; f <= last; ++f) {
        const std::string expected = fileBytes(a / pbf::frameFileName(f));
        ASSERT_FALSE(expected.empty()) << f;
        EXPECT_TRUE(expected == fileBytes(b / pbf::frameFileName(f)))
            << "frame " << f << " differs";
    }
}

std::string expectIoError(const std::function<void()>& action) {
    try {
        action();
    } catch (const pbf::IoError& e) {
        return e.what();
    }
    ADD_FAILURE() << "no IoError";
    return {};
}

// The crash is simulated by an exception thrown from the frame callback after
// frame 5 was written; the last periodic checkpoint is the one of frame 3.
TEST(Checkpoint, ResumedRunWritesBitIdenticalFrames) {
    const pbf::test::ThreadCountScope oneThread(1);
    const pbf::Scene scene = smallDamBreak();
    const fs::path straight = freshTestDirectory("straight");
    pbf::runScene(withOutput(scene, straight, kFrames), {});

    const fs::path crashed = freshTestDirectory("crashed");
    pbf::RunOptions options;
    options.onFrame = [](const pbf::FrameReport& r) {
        if (r.frame == 5) throw std::runtime_error("simulated crash");
    };
    EXPECT_THROW(pbf::runScene(withOutput(scene, crashed, kFrames), options), std::runtime_error);
    EXPECT_EQ(pbf::readCheckpoint(crashed / pbf::kCheckpointFileName).frame, 3);

    options.onFrame = nullptr;
    options.resume = true;
    const pbf::RunSummary resumed = pbf::runScene(withOutput(scene, crashed, kFrames), options);
    EXPECT_EQ(resumed.resumedFromFrame, 3);
    EXPECT_EQ(resumed.frames, kFrames);
    expectSameFrames(straight, crashed, 0, kFrames);
    // stats.csv has one row per frame, none twice (timing columns differ).
    std::ifstream csv(crashed / "stats.csv");
    std::string line;
    int rows = -1;
    while (std::getline(csv, line)) ++rows;
    EXPECT_EQ(rows, kFrames + 1);
    // The flow moved: the comparison is of a real flow, not of a frozen state.
    EXPECT_NE(fileBytes(straight / pbf::frameFileName(0)),
              fileBytes(straight / pbf::frameFileName(kFrames)));
    fs::remove_all(straight);
    fs::remove_all(crashed);
}

// A run of k frames, then a resume to more frames in a fresh process state:
// the checkpoint written at the end of a run is also a resume point.
TEST(Checkpoint, ExtendingAFinishedRunMatchesALongerRun) {
    const pbf::test::ThreadCountScope oneThread(1);
    const pbf::Scene scene = smallDamBreak();
    const fs::path straight = freshTestDirectory("long");
    pbf::runScene(withOutput(scene, straight, 5), {});
    const fs::path extended = freshTestDirectory("extended");
    pbf::runScene(withOutput(scene, extended, 2), {});
    pbf::RunOptions more;
    more.resume = true;
    EXPECT_EQ(pbf::runScene(withOutput(scene, extended, 5), more).resumedFromFrame, 2);
    expectSameFrames(straight, extended, 0, 5);
    fs::remove_all(straight);
    fs::remove_all(extended);
}

TEST(Checkpoint, SimulationStateRoundTripsThroughAFile) {
    const pbf::test::ThreadCountScope oneThread(1);
    const pbf::Scene scene = smallDamBreak();
    pbf::World original(scene);
    for (int f = 0; f < 3; ++f) pbf::test::stepFrame(original);
    const fs::path dir = freshTestDirectory("roundtrip");
    pbf::Checkpoint saved = pbf::captureCheckpoint(original, scene.fingerprint);
    saved.totals.statsCsv = "header\nrow\n";
    saved.totals.substeps = 42;
    pbf::writeCheckpoint(dir / "c.pbfck", saved);

    const pbf::Checkpoint loaded = pbf::readCheckpoint(dir / "c.pbfck");
    EXPECT_EQ(loaded.frame, 3);
    EXPECT_EQ(loaded.totals.statsCsv, "header\nrow\n");
    EXPECT_EQ(loaded.totals.substeps, 42);
    pbf::World restored(scene);
    pbf::restoreCheckpoint(loaded, restored, scene.fingerprint, "c.pbfck");
    EXPECT_EQ(restored.frame(), 3);
    EXPECT_EQ(restored.particles().id, original.particles().id);  // memory order kept
    EXPECT_EQ(restored.particles().nextId(), original.particles().nextId());
    pbf::test::stepFrame(original);
    pbf::test::stepFrame(restored);
    const auto& a = original.particles();
    const auto& b = restored.particles();
    ASSERT_EQ(a.size(), b.size());
    EXPECT_EQ(std::memcmp(a.position.y.data(), b.position.y.data(), a.size() * sizeof(float)), 0);
    EXPECT_EQ(std::memcmp(a.velocity.x.data(), b.velocity.x.data(), a.size() * sizeof(float)), 0);
    EXPECT_EQ(std::memcmp(a.density.data(), b.density.data(), a.size() * sizeof(float)), 0);
    fs::remove_all(dir);
}

// Ids and the next id are 64-bit in the file: a run that created more than
// 2^32 particles resumes with the same ids.
TEST(Checkpoint, IdsPastThirtyTwoBitsRoundTrip) {
    pbf::Checkpoint saved;
    saved.pbfVersion = "test";
    saved.particles.setNextId((std::uint64_t{1} << 32) - 2);
    for (int k = 0; k < 5; ++k) saved.particles.add({float(k), 0, 0}, {}, 1000.0f);
    const fs::path dir = freshTestDirectory("wide_ids");
    pbf::writeCheckpoint(dir / "c.pbfck", saved);
    const pbf::Checkpoint loaded = pbf::readCheckpoint(dir / "c.pbfck");
    ASSERT_EQ(loaded.particles.size(), 5u);
    for (std::size_t k = 0; k < 5; ++k) {
        EXPECT_EQ(loaded.particles.id[k], (std::uint64_t{1} << 32) - 2 + k);
        EXPECT_EQ(loaded.particles.position.x[k], float(k));
    }
    EXPECT_EQ(loaded.particles.nextId(), (std::uint64_t{1} << 32) + 3);
    fs::remove_all(dir);
}

TEST(Checkpoint, DamagedCheckpointsAreRefusedWithAClearError) {
    const pbf::test::ThreadCountScope oneThread(1);
    const pbf::Scene scene = smallDamBreak();
    const fs::path dir = freshTestDirectory("damaged");
    pbf::World world(scene);
    pbf::writeCheckpoint(dir / "good.pbfck", pbf::captureCheckpoint(world, scene.fingerprint));
    const std::string good = fileBytes(dir / "good.pbfck");

    std::ofstream(dir / "truncated.pbfck", std::ios::binary) << good.substr(0, good.size() / 2);
    EXPECT_NE(
        expectIoError([&] { pbf::readCheckpoint(dir / "truncated.pbfck"); }).find("truncated"),
        std::string::npos);

    std::string flipped = good;
    flipped[good.size() - 100] = static_cast<char>(flipped[good.size() - 100] ^ 0x10);
    std::ofstream(dir / "flipped.pbfck", std::ios::binary) << flipped;
    EXPECT_NE(expectIoError([&] { pbf::readCheckpoint(dir / "flipped.pbfck"); }).find("checksum"),
              std::string::npos);

    std::ofstream(dir / "foreign.pbfck", std::ios::binary)
        << "ply\nformat binary_little_endian 1.0\n......";
    const std::string foreign = expectIoError([&] { pbf::readCheckpoint(dir / "foreign.pbfck"); });
    EXPECT_NE(foreign.find("foreign.pbfck"), std::string::npos);
    EXPECT_NE(foreign.find("not a pbf checkpoint"), std::string::npos);

    std::string older = good;
    older[8] = 4;  // the format before 64-bit ids
    std::ofstream(dir / "older.pbfck", std::ios::binary) << older;
    const std::string olderError = expectIoError([&] { pbf::readCheckpoint(dir / "older.pbfck"); });
    EXPECT_NE(olderError.find("older.pbfck"), std::string::npos);
    EXPECT_NE(olderError.find("format version 4 was written by an older pbf"), std::string::npos);
    EXPECT_NE(olderError.find("without --resume"), std::string::npos);

    std::string future = good;
    future[8] = 99;  // format version
    std::ofstream(dir / "future.pbfck", std::ios::binary) << future;
    EXPECT_NE(
        expectIoError([&] { pbf::readCheckpoint(dir / "future.pbfck"); }).find("format version 99"),
        std::string::npos);
    fs::remove_all(dir);
}

TEST(Checkpoint, ResumeWithAnotherSceneOrWithoutCheckpointIsRefused) {
    const pbf::test::ThreadCountScope oneThread(1);
    const fs::path dir = freshTestDirectory("othersc");
    pbf::runScene(withOutput(smallDamBreak(), dir, 2), {});
    pbf::RunOptions resume;
    resume.resume = true;
    const pbf::Scene other = smallDamBreak({pbf::parseOverride("solver.iterations=5")});
    EXPECT_NE(expectIoError([&] {
                  pbf::runScene(withOutput(other, dir, 4), resume);
              }).find("different scene"),
              std::string::npos);
    // Nothing was overwritten by the refused resume.
    EXPECT_FALSE(fs::exists(dir / pbf::frameFileName(3)));

    const fs::path empty = freshTestDirectory("nockpt");
    EXPECT_NE(expectIoError([&] {
                  pbf::runScene(withOutput(smallDamBreak(), empty, 4), resume);
              }).find("no checkpoint to resume from"),
              std::string::npos);
    fs::remove_all(dir);
    fs::remove_all(empty);
}

TEST(Checkpoint, FingerprintIgnoresFormattingAndOutputSettingsOnly) {
    const pbf::test::ThreadCountScope oneThread(1);
    using pbf::test::smallSceneJson;
    const auto fingerprint = [](const std::string& json, std::vector<pbf::SceneOverride> o = {}) {
        return pbf::parseScene(json, "s.json", o).fingerprint;
    };
    const std::uint64_t base = fingerprint(smallSceneJson());
    EXPECT_EQ(base, fingerprint(smallSceneJson(R"("output": {"frames": 7, "directory": "elsewhere",
                                                  "checkpoint_every": 3}, "guard": {"max_speed": 50})")));
    EXPECT_EQ(base, fingerprint(smallSceneJson(), {pbf::parseOverride("output.frames=12")}));
    EXPECT_NE(base, fingerprint(smallSceneJson(), {pbf::parseOverride("solver.iterations=5")}));
    EXPECT_NE(base, fingerprint(smallSceneJson(R"("output": {"fps": 60})")));
    EXPECT_NE(base, fingerprint(smallSceneJson(R"("gravity": [0, -9.0, 0])")));
}

}  // namespace

namespace {

// A nozzle pouring onto a mesh solid: the emitters' progress is part of the
// state, so a resumed run must emit exactly the same particles.
TEST(Checkpoint, ResumeWithEmittersAndSolidsIsBitIdentical) {
    const pbf::test::ThreadCountScope oneThread(1);
    const pbf::Scene scene = pbf::loadScene(pbf::test::scenePath("pour_bunny.json"),
                                            {pbf::parseOverride("particle_radius=0.016")});
    const fs::path straight = freshTestDirectory("pour_straight");
    pbf::runScene(withOutput(scene, straight, 8), {});
    const fs::path crashed = freshTestDirectory("pour_crashed");
    pbf::RunOptions options;
    options.onFrame = [](const pbf::FrameReport& r) {
        if (r.frame == 5) throw std::runtime_error("simulated crash");
    };
    EXPECT_THROW(pbf::runScene(withOutput(scene, crashed, 8), options), std::runtime_error);
    options.onFrame = nullptr;
    options.resume = true;
    EXPECT_EQ(pbf::runScene(withOutput(scene, crashed, 8), options).resumedFromFrame, 3);
    expectSameFrames(straight, crashed, 0, 8);
    // Water was being emitted across the resume point.
    EXPECT_LT(pbf::readParticlesPly(straight / pbf::frameFileName(3)).position.size(),
              pbf::readParticlesPly(straight / pbf::frameFileName(8)).position.size());
    fs::remove_all(straight);
    fs::remove_all(crashed);
}

// Surface tension keeps no state between steps (the surface flags come from
// each step's densities, the capillary time step from the parameters), so a
// resumed run continues with the same bits; this fails if the pass ever
// reads something a checkpoint does not store. A checkpoint of a run with
// another surface tension is refused (the fingerprint holds the parameter).
TEST(Checkpoint, ResumeWithSurfaceTensionIsBitIdentical) {
    const pbf::test::ThreadCountScope oneThread(1);
    const pbf::Scene scene = smallDamBreak({pbf::parseOverride("fluid.surface_tension=0.0728"),
                                            pbf::parseOverride("solver.wall_adhesion=0.5")});
    const fs::path straight = freshTestDirectory("tension_straight");
    pbf::runScene(withOutput(scene, straight, kFrames), {});
    const fs::path crashed = freshTestDirectory("tension_crashed");
    pbf::RunOptions options;
    options.onFrame = [](const pbf::FrameReport& r) {
        if (r.frame == 5) throw std::runtime_error("simulated crash");
    };
    EXPECT_THROW(pbf::runScene(withOutput(scene, crashed, kFrames), options), std::runtime_error);
    options.onFrame = nullptr;
    options.resume = true;
    const pbf::Scene weaker = smallDamBreak({pbf::parseOverride("fluid.surface_tension=0.05"),
                                             pbf::parseOverride("solver.wall_adhesion=0.5")});
    EXPECT_NE(expectIoError([&] {
                  pbf::runScene(withOutput(weaker, crashed, kFrames), options);
              }).find("different scene"),
              std::string::npos);
    EXPECT_EQ(pbf::runScene(withOutput(scene, crashed, kFrames), options).resumedFromFrame, 3);
    expectSameFrames(straight, crashed, 0, kFrames);
    // The pass ran: without surface tension the last frame differs.
    const fs::path plain = freshTestDirectory("tension_plain");
    pbf::runScene(withOutput(smallDamBreak(), plain, kFrames), {});
    EXPECT_NE(fileBytes(plain / pbf::frameFileName(kFrames)),
              fileBytes(straight / pbf::frameFileName(kFrames)));
    fs::remove_all(straight);
    fs::remove_all(crashed);
    fs::remove_all(plain);
}

// The warm start carries each particle's last solve acceleration from step
// to step; the checkpoint stores it (format 4), so a resumed run continues
// with the same bits. Checked that this can fail: with the array left out
// of the checkpoint, the resumed frames differ from frame 4 on.
TEST(Checkpoint, ResumeWithWarmStartAndToleranceIsBitIdentical) {
    const pbf::test::ThreadCountScope oneThread(1);
    const pbf::Scene scene = smallDamBreak({pbf::parseOverride("solver.warm_start=0.8"),
                                            pbf::parseOverride("solver.over_relaxation=1.2"),
                                            pbf::parseOverride("solver.max_density_error=0.001")});
    const fs::path straight = freshTestDirectory("warm_straight");
    pbf::runScene(withOutput(scene, straight, kFrames), {});
    const fs::path crashed = freshTestDirectory("warm_crashed");
    pbf::RunOptions options;
    options.onFrame = [](const pbf::FrameReport& r) {
        if (r.frame == 5) throw std::runtime_error("simulated crash");
    };
    EXPECT_THROW(pbf::runScene(withOutput(scene, crashed, kFrames), options), std::runtime_error);
    EXPECT_EQ(pbf::readCheckpoint(crashed / pbf::kCheckpointFileName)
                  .particles.solveAcceleration.x.size(),
              pbf::readParticlesPly(straight / pbf::frameFileName(3)).position.size());
    options.onFrame = nullptr;
    options.resume = true;
    EXPECT_EQ(pbf::runScene(withOutput(scene, crashed, kFrames), options).resumedFromFrame, 3);
    expectSameFrames(straight, crashed, 0, kFrames);
    fs::remove_all(straight);
    fs::remove_all(crashed);
}

}  // namespace
