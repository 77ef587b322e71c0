// Prescribed motions: the pose at time t against its closed form, and the
// velocities the water feels against the pose's rate of change (a central
// difference), for every kind; keyframes hold outside their span; the CSV
// file's reader (pbf/io/motion_file.hpp) and the validation name the field.
#include "pbf/geometry/prescribed_motion.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>

#include "pbf/core/errors.hpp"
#include "pbf/io/motion_file.hpp"

namespace pbf {
namespace {

// The material velocity at a few points of the solid against the central
// difference of where those points are (a rigid motion is fixed by any
// three points not on a line).
void expectVelocitiesMatchTheMotion(const PrescribedMotion& m, const Pose& rest, const Vec3& pivot,
                                    double t) {
    const double h = 1e-4;
    const SolidMotion now = motionAt(m, rest, pivot, t);
    const SolidMotion before = motionAt(m, rest, pivot, t - h);
    const SolidMotion after = motionAt(m, rest, pivot, t + h);
    for (const Vec3& local : {Vec3{0, 0, 0}, Vec3{0.2f, 0, 0}, Vec3{0, 0.1f, -0.3f}}) {
        const Vec3 a = before.pose.toWorld(local), b = after.pose.toWorld(local);
        const Vec3 rate = (b - a) * float(1.0 / (2.0 * h));
        const Vec3 v = now.velocityAt(now.pose.toWorld(local));
        EXPECT_NEAR(v.x, rate.x, 2e-3) << "t " << t;
        EXPECT_NEAR(v.y, rate.y, 2e-3) << "t " << t;
        EXPECT_NEAR(v.z, rate.z, 2e-3) << "t " << t;
    }
}

TEST(PrescribedMotion, AnOscillationFollowsItsSine) {
    PrescribedMotion m;
    m.kind = PrescribedMotion::Kind::Oscillate;
    m.amplitude = {0.05f, 0.0f, 0.02f};
    m.period = 0.8f;
    m.phaseDegrees = 30.0f;
    const Vec3 pivot{0.5f, 0.2f, 0.1f};
    for (double t : {0.0, 0.13, 0.41, 1.7}) {
        const double phase = 2.0 * std::numbers::pi * t / 0.8 + std::numbers::pi / 6.0;
        const SolidMotion s = motionAt(m, Pose{}, pivot, t);
        EXPECT_NEAR(s.pose.position.x, 0.05 * std::sin(phase), 1e-6);
        EXPECT_NEAR(s.pose.position.z, 0.02 * std::sin(phase), 1e-6);
        EXPECT_NEAR(s.velocity.x, 0.05 * 2.0 * std::numbers::pi / 0.8 * std::cos(phase), 1e-5);
        expectVelocitiesMatchTheMotion(m, Pose{}, pivot, t);
    }
    // An angle too, about the pivot: the pivot itself only translates.
    m.angleAmplitude = 20.0f;
    m.axis = {0, 0, 2};
    for (double t : {0.05, 0.3, 0.77}) {
        const SolidMotion s = motionAt(m, Pose{}, pivot, t);
        const Vec3 p = s.pose.toWorld(pivot);
        const SolidMotion translated = [&] {
            PrescribedMotion only = m;
            only.angleAmplitude = 0.0f;
            return motionAt(only, Pose{}, pivot, t);
        }();
        EXPECT_NEAR(length(p - translated.pose.toWorld(pivot)), 0.0, 1e-6);
        expectVelocitiesMatchTheMotion(m, Pose{}, pivot, t);
    }
}

TEST(PrescribedMotion, ARotationTurnsAboutItsPivotAtItsSpeed) {
    PrescribedMotion m;
    m.kind = PrescribedMotion::Kind::Rotate;
    m.axis = {0, 1, 0};
    m.speedDegrees = 90.0f;  // a quarter turn per second
    const Vec3 pivot{1.0f, 0.0f, 1.0f};
    // A mesh resting 0.3 m from the pivot along x, turned 10 degrees about z.
    const Pose rest{{1.3f, 0.2f, 1.0f}, axisAngle({0, 0, 1}, 0.1745f)};
    const SolidMotion s = motionAt(m, rest, pivot, 1.0);
    // After a quarter turn about +y, +x goes to -z.
    EXPECT_NEAR(s.pose.position.x, 1.0, 1e-5);
    EXPECT_NEAR(s.pose.position.y, 0.2, 1e-6);
    EXPECT_NEAR(s.pose.position.z, 0.7, 1e-5);
    EXPECT_NEAR(s.angularVelocity.y, std::numbers::pi / 2.0, 1e-6);
    // After 100 turns it is where it was (the angle is kept modulo a turn).
    const SolidMotion later = motionAt(m, rest, pivot, 400.0);
    EXPECT_NEAR(length(later.pose.position - rest.position), 0.0, 1e-5);
    for (double t : {0.0, 0.37, 2.9}) expectVelocitiesMatchTheMotion(m, rest, pivot, t);
}

TEST(PrescribedMotion, KeyframesInterpolateAndHoldOutsideTheirSpan) {
    PrescribedMotion m;
    m.kind = PrescribedMotion::Kind::Keyframes;
    m.keys = {{0.5, {0, 0, 0}, {0, 0, 0}},
              {1.5, {0.2f, 0.1f, 0}, {0, 90, 0}},
              {2.0, {0.2f, 0.1f, 0}, {0, 90, 30}}};
    const Vec3 pivot{0.1f, 0.1f, 0.1f};
    const SolidMotion start = motionAt(m, Pose{}, pivot, 0.0);
    EXPECT_EQ(start.pose.position, (Vec3{}));
    EXPECT_EQ(start.velocity, (Vec3{}));
    const SolidMotion middle = motionAt(m, Pose{}, pivot, 1.0);  // half way: 45 degrees about y
    EXPECT_NEAR(middle.pose.toWorld(pivot).x, 0.2, 1e-6);        // the pivot moved by 0.1
    EXPECT_NEAR(middle.pose.toWorld(pivot).y, 0.15, 1e-6);
    EXPECT_NEAR(middle.angularVelocity.y, (std::numbers::pi / 2.0) / 1.0, 1e-5);
    const Quat q = middle.pose.orientation;
    EXPECT_NEAR(2.0 * std::acos(std::min(1.0f, std::fabs(q.w))), std::numbers::pi / 4.0, 1e-5);
    const SolidMotion end = motionAt(m, Pose{}, pivot, 5.0);
    EXPECT_EQ(end.velocity, (Vec3{}));
    EXPECT_EQ(end.angularVelocity, (Vec3{}));
    for (double t : {0.7, 1.2, 1.8}) expectVelocitiesMatchTheMotion(m, Pose{}, pivot, t);
}

// First-order wave-maker theory (Dean & Dalrymple 1991, sec. 6.2): the
// dispersion relation's root, the transfer functions' limits (piston: H/S =
// kh in shallow water, 2 in deep; flap: kh/2 and 2 (1 - 1/kh)) and their values at
// kh = 1 (0.9818 and 0.5281, evaluated by hand from the closed forms).
TEST(PrescribedMotion, WaveMakersFollowBiesel) {
    for (const double depth : {0.05, 0.3, 3.0}) {
        const double k = waveNumber(1.2, depth);
        const double omega = 2.0 * std::numbers::pi / 1.2;
        EXPECT_NEAR(9.81 * k * std::tanh(k * depth), omega * omega, 1e-9 * omega * omega);
    }
    PrescribedMotion piston;
    piston.kind = PrescribedMotion::Kind::Piston;
    piston.waveHeight = 0.02f;
    PrescribedMotion flap = piston;
    flap.kind = PrescribedMotion::Kind::Flap;
    // The period that makes k h = 1 in 0.3 m of water: omega^2 = g k tanh(1).
    const double h = 0.3, k = 1.0 / h;
    const double period = 2.0 * std::numbers::pi / std::sqrt(9.81 * k * std::tanh(1.0));
    piston.depth = flap.depth = float(h);
    piston.period = flap.period = float(period);
    EXPECT_NEAR(waveMakerOf(piston).waveNumber * h, 1.0, 1e-6);
    EXPECT_NEAR(waveMakerOf(piston).heightPerStroke, 0.9818, 1e-4);
    EXPECT_NEAR(waveMakerOf(flap).heightPerStroke, 0.5281, 1e-4);
    EXPECT_NEAR(waveMakerOf(piston).stroke, 0.02 / 0.9818, 1e-5);
    // Shallow (k h = 0.05) and deep (k h = 10) water.
    piston.depth = flap.depth = 0.002f;
    piston.period = flap.period =
        float(2.0 * std::numbers::pi / std::sqrt(9.81 * 25.0 * std::tanh(0.05)));
    EXPECT_NEAR(waveMakerOf(piston).heightPerStroke, 0.05, 2e-3);
    EXPECT_NEAR(waveMakerOf(flap).heightPerStroke, 0.025, 1e-3);
    piston.depth = flap.depth = 2.0f;
    piston.period = flap.period =
        float(2.0 * std::numbers::pi / std::sqrt(9.81 * 5.0 * std::tanh(10.0)));
    EXPECT_NEAR(waveMakerOf(piston).heightPerStroke, 2.0, 1e-3);
    // The flap tends to the piston's 2 as 2 (1 - 1/kh): its hinge's depth
    // matters less as the wave's motion dies out above it.
    EXPECT_NEAR(waveMakerOf(flap).heightPerStroke, 1.8, 1e-3);
}

// The paddles move as the theory asks: after the ramp a piston's face
// swings S / 2 each way, a flap's face at the still-water level too (a turn
// about the hinge on the floor), and the water feels the motion's rates,
// through the ramp as after it.
TEST(PrescribedMotion, WaveMakersSwingTheirStroke) {
    PrescribedMotion m;
    m.kind = PrescribedMotion::Kind::Piston;
    m.waveHeight = 0.03f;
    m.period = 1.0f;
    m.depth = 0.25f;
    m.direction = {0, 0, 2};  // along +z
    const double half = 0.5 * waveMakerOf(m).stroke;
    EXPECT_EQ(waveMakerOf(m).rampSeconds, 2.0);
    const Vec3 pivot{0.1f, 0.0f, 0.1f};
    EXPECT_NEAR(motionAt(m, Pose{}, pivot, 2.25).pose.position.z, half, 1e-6);  // a crest
    EXPECT_NEAR(motionAt(m, Pose{}, pivot, 2.75).pose.position.z, -half, 1e-6);
    EXPECT_LT(std::fabs(motionAt(m, Pose{}, pivot, 0.25).pose.position.z), 0.2 * half);  // ramping
    for (double t : {0.3, 1.1, 2.6}) expectVelocitiesMatchTheMotion(m, Pose{}, pivot, t);

    m.kind = PrescribedMotion::Kind::Flap;
    m.hasPivot = true;
    m.pivot = {0.1f, 0.0f, 0.1f};
    const double flapHalf = 0.5 * waveMakerOf(m).stroke;
    const Vec3 face{0.1f, 0.25f, 0.1f};  // the paddle at the still-water level
    const SolidMotion crest = motionAt(m, Pose{}, m.pivot, 2.25);
    // tan(angle) = (S / 2) / h: the face moves S / 2 along z (and dips a little).
    EXPECT_NEAR(crest.pose.toWorld(face).z - face.z,
                flapHalf * std::cos(std::atan(flapHalf / 0.25)), 1e-6);
    EXPECT_NEAR(crest.pose.toWorld(m.pivot).z, m.pivot.z, 1e-6);  // the hinge stays
    for (double t : {0.3, 1.1, 2.6}) expectVelocitiesMatchTheMotion(m, Pose{}, m.pivot, t);
}

TEST(PrescribedMotion, BadMotionsAreRefusedByField) {
    PrescribedMotion m;
    m.kind = PrescribedMotion::Kind::Oscillate;
    m.amplitude = {0.1f, 0, 0};
    m.period = 0.0f;
    EXPECT_EQ(validate(m, "solids[1].motion").rfind("solids[1].motion.period: must be positive", 0),
              0u);
    m.period = 1.0f;
    m.amplitude = {};
    EXPECT_NE(validate(m, "solids[1].motion").find("needs an amplitude"), std::string::npos);
    m.kind = PrescribedMotion::Kind::Keyframes;
    m.keys = {{0.0, {}, {}}, {1.0, {}, {}}, {0.5, {}, {}}};
    EXPECT_EQ(validate(m, "solids[0].motion"),
              "solids[0].motion.keys[2].time: keyframes must be in increasing time (0.5 s after 1 "
              "s)");
    m.keys.resize(1);
    EXPECT_NE(validate(m, "solids[0].motion").find("at least two keyframes"), std::string::npos);
    m.kind = PrescribedMotion::Kind::Rotate;
    m.speedDegrees = 0.0f;
    EXPECT_NE(validate(m, "solids[0].motion").find("solids[0].motion.speed"), std::string::npos);
    // Wave makers: a wave that breaks, a stroke beyond the theory, a flap
    // without its hinge.
    PrescribedMotion waves;
    waves.kind = PrescribedMotion::Kind::Piston;
    waves.period = 1.0f;
    waves.depth = 0.2f;
    waves.waveHeight = 0.3f;
    EXPECT_NE(validate(waves, "solids[0].motion").find("solids[0].motion.wave_height: 0.3 m waves"),
              std::string::npos)
        << validate(waves, "solids[0].motion");
    EXPECT_NE(validate(waves, "solids[0].motion").find("Miche"), std::string::npos);
    waves.period = 10.0f;  // long waves in shallow water: a huge stroke
    waves.waveHeight = 0.05f;
    EXPECT_NE(validate(waves, "solids[0].motion").find("need a stroke of"), std::string::npos)
        << validate(waves, "solids[0].motion");
    waves.period = 1.0f;
    waves.waveHeight = 0.02f;
    EXPECT_EQ(validate(waves, "solids[0].motion"), "");
    waves.depth = 0.0f;
    EXPECT_NE(validate(waves, "solids[0].motion").find("solids[0].motion.depth"),
              std::string::npos);
    waves.depth = 0.2f;
    waves.kind = PrescribedMotion::Kind::Flap;
    EXPECT_NE(validate(waves, "solids[0].motion").find("solids[0].motion.pivot"),
              std::string::npos);
}

TEST(PrescribedMotion, KeyframesFromACsvFile) {
    const auto dir = std::filesystem::temp_directory_path() / "pbf_motion_csv";
    std::filesystem::create_directories(dir);
    const auto good = dir / "paddle.csv";
    std::ofstream(good)
        << "time, x, y, z, ry\n0, 0, 0, 0, 0\n0.5, 0.1, 0, 0, 10\n\n1.0, 0, 0, 0, 0\n";
    const std::vector<MotionKey> keys = readMotionCsv(good.string(), "solids[0].motion.file");
    ASSERT_EQ(keys.size(), 3u);
    EXPECT_EQ(keys[1].time, 0.5);
    EXPECT_EQ(keys[1].position.x, 0.1f);
    EXPECT_EQ(keys[1].rotationDegrees.y, 10.0f);
    EXPECT_EQ(keys[1].rotationDegrees.x, 0.0f);
    const auto missing = dir / "no_z.csv";
    std::ofstream(missing) << "time,x,y\n0,0,0\n";
    try {
        readMotionCsv(missing.string(), "solids[0].motion.file");
        FAIL() << "a file without z was read";
    } catch (const SceneError& e) {
        EXPECT_NE(std::string(e.what()).find("no column 'z'"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("no_z.csv"), std::string::npos) << e.what();
    }
    const auto bad = dir / "bad.csv";
    std::ofstream(bad) << "time,x,y,z\n0,0,0,zero\n";
    try {
        readMotionCsv(bad.string(), "solids[0].motion.file");
        FAIL() << "a word was read as a number";
    } catch (const SceneError& e) {
        EXPECT_NE(std::string(e.what()).find("bad.csv:2: z: not a number"), std::string::npos)
            << e.what();
    }
    std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace pbf
