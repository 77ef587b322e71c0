// Solids with a prescribed motion (solids[i].motion) in a World: the water
// feels where they are and how fast they move, resuming mid-motion is exact,
// and scene files name a bad motion's field.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "pbf/io/scene.hpp"
#include "pbf/world/world.hpp"
#include "support/test_util.hpp"

namespace {

// A 0.4 x 0.15 x 0.4 m tank of water with a paddle (a 0.2 x 0.12 x 0.02 m
// box standing at the centre) driven by `motion`.
std::string mixerJson(const std::string& motion) {
    return R"({"name": "mixer", "particle_radius": 0.01,
      "domain": {"min": [0, 0, 0], "max": [0.4, 0.25, 0.4]},
      "fluid_blocks": [{"min": [0, 0, 0], "max": [0.4, 0.15, 0.4]}],
      "solids": [{"type": "box", "min": [0.1, 0.02, 0.19], "max": [0.3, 0.14, 0.21],
                  "motion": )" +
           motion + R"(}],
      "output": {"fps": 30}})";
}

// The water's angular momentum about the vertical axis through the tank's
// centre (per unit particle mass), m^2/s.
double spin(const pbf::World& world) {
    const pbf::ParticleStore& p = world.particles();
    double l = 0.0;
    for (std::size_t i = 0; i < p.size(); ++i) {
        const double x = p.position.x[i] - 0.2, z = p.position.z[i] - 0.2;
        l += z * p.velocity.x[i] - x * p.velocity.z[i];
    }
    return l;
}

// A paddle turning about +y spins the water up the same way (its angular
// momentum about y grows with the sense of the turn), and the water never
// enters it: the boundary sees the paddle where it is, moving as it moves.
// On every backend (the motion lives in the World; a backend sees the pose
// and the velocity through the solids).
class DrivenSolidsOn : public ::testing::TestWithParam<pbf::BackendKind> {};

TEST_P(DrivenSolidsOn, ATurningPaddleSpinsTheWaterItsWay) {
    if (!pbf::deviceInfo(GetParam()).usable) GTEST_SKIP() << "backend not usable here";
    pbf::WorldOptions options;
    options.backend = GetParam();
    const std::vector<float> senses = GetParam() == pbf::BackendKind::Cpu
                                          ? std::vector<float>{1.0f, -1.0f}
                                          : std::vector<float>{-1.0f};
    for (const float sense : senses) {
        SCOPED_TRACE(sense);
        pbf::World world(
            pbf::parseScene(mixerJson(R"({"type": "rotate", "axis": [0, 1, 0], "speed": )" +
                                      std::to_string(120.0f * sense) + "}"),
                            "mixer.json"),
            options);
        double previous = 0.0;
        for (int frame = 1; frame <= 30; ++frame) {
            const pbf::FrameReport r = pbf::test::stepFrame(world);
            EXPECT_EQ(r.state.insideSolid, 0u) << "frame " << frame;
            EXPECT_EQ(r.state.escaped, 0u) << "frame " << frame;
            if (frame % 10 == 0) {
                const double l = spin(world) * sense;  // > 0: the paddle's sense
                EXPECT_GT(l, previous) << "frame " << frame;
                previous = l;
            }
        }
        // The paddle turned 120 degrees in 1 s: it is where the rotation
        // puts it (a quarter of the way past 90).
        const pbf::Pose pose = world.solidMotion(0).pose;
        const pbf::Vec3 end = pose.toWorld({0.3f, 0.08f, 0.2f});  // the end that was at +x
        EXPECT_NEAR(end.x, 0.2 + 0.1 * std::cos(120.0 * M_PI / 180.0), 1e-4);
        EXPECT_NEAR(end.z, 0.2 - sense * 0.1 * std::sin(120.0 * M_PI / 180.0), 1e-4);
    }
}

INSTANTIATE_TEST_SUITE_P(Backends, DrivenSolidsOn, pbf::test::everyBackendHere(),
                         pbf::test::backendTestName);

// The state at frame 10 of a run with an oscillating paddle, restored into a
// new World, continues bit for bit as the run did: the motion is a function
// of time, and a resumed World places its solids at the state's time.
TEST(DrivenSolids, ResumingMidMotionIsBitIdentical) {
    const pbf::Scene scene = pbf::parseScene(
        mixerJson(R"({"type": "oscillate", "amplitude": [0.03, 0, 0], "angle_amplitude": 15,
                      "axis": [0, 1, 0], "period": 0.5})"),
        "shaken.json");
    pbf::World straight(scene);
    for (int frame = 0; frame < 10; ++frame) pbf::test::stepFrame(straight);
    pbf::World resumed(scene);
    resumed.restoreState(straight.captureState());
    EXPECT_EQ(resumed.solidMotion(0).pose.position, straight.solidMotion(0).pose.position);
    for (int frame = 0; frame < 5; ++frame) {
        pbf::test::stepFrame(straight);
        pbf::test::stepFrame(resumed);
    }
    const pbf::WorldState a = straight.captureState(), b = resumed.captureState();
    EXPECT_EQ(a.particles.position.x, b.particles.position.x);
    EXPECT_EQ(a.particles.position.y, b.particles.position.y);
    EXPECT_EQ(a.particles.velocity.z, b.particles.velocity.z);
}

TEST(DrivenSolids, ScriptsCannotMoveADrivenSolid) {
    pbf::World world(pbf::parseScene(mixerJson(R"({"type": "rotate", "speed": 30})"), "m.json"));
    try {
        world.setSolidMotion(0, {});
        FAIL() << "a driven solid was moved by a script";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("solids[0].motion"), std::string::npos) << e.what();
    }
}

std::string sceneError(const std::string& motion, const std::string& name = "bad.json") {
    try {
        pbf::World world(pbf::parseScene(mixerJson(motion), name));
    } catch (const pbf::SceneError& e) {
        return e.what();
    }
    return "(accepted)";
}

TEST(DrivenSolids, BadMotionsAreRefusedNamingTheField) {
    EXPECT_NE(sceneError(R"({"type": "oscillate", "amplitude": [0.1, 0, 0], "period": 0})")
                  .find("solids[0].motion.period: must be positive"),
              std::string::npos);
    EXPECT_NE(sceneError(R"({"type": "keyframes", "keys": [{"time": 1}, {"time": 0.5}]})")
                  .find("solids[0].motion.keys[1].time: keyframes must be in increasing time"),
              std::string::npos);
    EXPECT_NE(sceneError(R"({"type": "wobble"})").find("solids[0].motion.type"), std::string::npos);
    EXPECT_NE(sceneError(R"({"type": "piston", "wave_height": 0.3, "period": 1, "depth": 0.15})")
                  .find("solids[0].motion.wave_height: 0.3 m waves of 1 s break"),
              std::string::npos);
    EXPECT_NE(sceneError(R"({"type": "flap", "wave_height": 0.01, "period": 1, "depth": 0.15})")
                  .find("solids[0].motion.pivot"),
              std::string::npos);
    EXPECT_NE(sceneError(R"({"type": "rotate", "speed": 10, "spead": 3})")
                  .find("solids[0].motion.spead: unknown key"),
              std::string::npos);
    EXPECT_NE(sceneError(R"({"type": "keyframes", "file": "no_such_motion.csv"})")
                  .find("solids[0].motion.file"),
              std::string::npos);
    // A rigid body moves by its forces.
    try {
        pbf::parseScene(R"({"particle_radius": 0.01, "domain": {"min": [0, 0, 0], "max": [1, 1, 1]},
          "fluid_blocks": [{"min": [0, 0, 0], "max": [1, 0.2, 1]}],
          "rigid_bodies": [{"type": "sphere", "center": [0.5, 0.5, 0.5], "radius": 0.1,
                            "density": 500, "motion": {"type": "rotate", "speed": 10}}]})",
                        "body.json");
        FAIL() << "a rigid body took a motion";
    } catch (const pbf::SceneError& e) {
        EXPECT_NE(std::string(e.what()).find("rigid_bodies[0].motion"), std::string::npos)
            << e.what();
    }
}

// Keyframes from a CSV file next to the scene move the solid as the file
// says.
TEST(DrivenSolids, KeyframesFromAFileNextToTheScene) {
    const auto dir = std::filesystem::temp_directory_path() / "pbf_driven_csv";
    std::filesystem::create_directories(dir);
    std::ofstream(dir / "paddle.csv") << "time,x,y,z\n0,0,0,0\n0.5,0.05,0,0\n1,0,0,0\n";
    std::ofstream(dir / "scene.json")
        << mixerJson(R"({"type": "keyframes", "file": "paddle.csv"})");
    pbf::World world(pbf::loadScene(dir / "scene.json"));
    for (int frame = 0; frame < 6; ++frame) pbf::test::stepFrame(world);  // 0.2 s
    EXPECT_NEAR(world.solidMotion(0).pose.position.x, 0.02, 1e-6);
    EXPECT_NEAR(world.solidMotion(0).velocity.x, 0.1, 1e-5);
    std::filesystem::remove_all(dir);
}

}  // namespace
