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
