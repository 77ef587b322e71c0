// The same tank of water near the origin and far from it. Positions are
// floats, whose spacing grows with their size (7.6 um at 100 m, 61 um at
// 1 km, 1 mm at 10 km), and the solver's corrections are micrometres: in
// world coordinates a tank at 10 km no longer rests (it stood 5 mm higher
// and 5 % less dense, with 17 times the residual motion). The World
// measures positions from its local frame (pbf/world/local_frame.hpp), so
// the same water runs the same anywhere (docs/performance.md, "Precision far
// from the origin").
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "pbf/io/scene.hpp"
#include "pbf/world/world.hpp"
#include "support/test_util.hpp"

namespace {

pbf::WorldDef tankAt(float offset, float width = 0.3f) {
    pbf::WorldDef def;
    def.name = "far";
    def.simulation.domain = {{offset, 0.0f, offset}, {offset + width, 0.4f, offset + width}};
    def.simulation.particleRadius = 0.01f;
    def.fluidBlocks.push_back(
        {{{offset, 0.0f, offset}, {offset + width, 0.2f, offset + width}}, {}});
    def.fps = 30.0f;
    return def;
}

struct Settled {
    std::size_t count = 0;
    double meanHeight = 0.0, meanDensity = 0.0, medianSpeed = 0.0;
};

Settled settle(float offset) {
    pbf::World world(tankAt(offset));
    for (int frame = 0; frame < 60; ++frame) pbf::test::stepFrame(world);
    const pbf::ParticleStore& p = world.particles();
    Settled s;
    s.count = p.size();
    std::vector<double> speeds;
    for (std::size_t i = 0; i < p.size(); ++i) {
        s.meanHeight += p.position.y[i];
        s.meanDensity += p.density[i];
        speeds.push_back(length(p.velocity.get(i)));
    }
    s.meanHeight /= double(s.count);
    s.meanDensity /= double(s.count);
    std::nth_element(speeds.begin(), speeds.begin() + speeds.size() / 2, speeds.end());
    s.medianSpeed = speeds[speeds.size() / 2];
    std::printf("  at %6.0f m: %zu particles, mean height %.5f m, mean density %.2f kg/m^3, "
                "median speed %.4f m/s\n",
                double(offset), s.count, s.meanHeight, s.meanDensity, s.medianSpeed);
    return s;
}

TEST(FarFromTheOrigin, TheSameTankSettlesTheSameAnywhere) {
    const Settled here = settle(0.0f);
    ASSERT_EQ(here.count, 2250u);  // 15 x 10 x 15
    for (const float offset : {100.0f, 1000.0f, 10000.0f}) {
        SCOPED_TRACE(offset);
        const Settled far = settle(offset);
        // The same lattice: a block written as 0.3 m wide at 1 km is stored a
        // few ulps short of it and lost a row before the lattice count
        // allowed for its corners' rounding.
        EXPECT_EQ(far.count, here.count);
        // The same water, to what a last-bit change anywhere moves a tank
        // still sloshing after 2 s (the frame at 100 m, or another compiler's
        // rounding, moves the mean density by up to 0.06 % and the height by
        // 0.2 mm): height to 1 mm, density to 0.5 %, residual motion within a
        // factor 3. In world coordinates the tank at 10 km stood 5.4 mm
        // higher, 4.7 % less dense, and moved at 323 mm/s against 19.
        EXPECT_NEAR(far.meanHeight, here.meanHeight, 1e-3);
        EXPECT_NEAR(far.meanDensity, here.meanDensity, 5e-3 * here.meanDensity);
        EXPECT_LT(far.medianSpeed, 3.0 * here.medianSpeed);
    }
}

// A tank whose coordinates are exact at 10 km too (0.3125 m = 320 float
// spacings there) has the same local definition as at the origin, so it
// runs bit for bit the same: the frame is all that separates them.
TEST(FarFromTheOrigin, AnExactlyPlacedTankRunsBitIdenticallyAtTenKilometres) {
    pbf::World here(tankAt(0.0f, 0.3125f));
    pbf::World far(tankAt(10000.0f, 0.3125f));
    EXPECT_FALSE(here.localFrame().shifted());
    EXPECT_EQ(far.localFrame().origin, (pbf::Vec3{10000.0f, 0.0f, 10000.0f}));
    for (int frame = 0; frame < 10; ++frame) {
        pbf::test::stepFrame(here);
        pbf::test::stepFrame(far);
    }
    const pbf::WorldState stateHere = here.captureState();
    const pbf::ParticleStore& a = stateHere.particles;
    const pbf::WorldState stateFar = far.captureState();
    const pbf::ParticleStore& b = stateFar.particles;
    ASSERT_EQ(a.size(), b.size());
    EXPECT_EQ(a.position.x, b.position.x);
    EXPECT_EQ(a.position.y, b.position.y);
    EXPECT_EQ(a.position.z, b.position.z);
    EXPECT_EQ(a.velocity.x, b.velocity.x);
    // The API speaks world coordinates: the local position plus the origin.
    const pbf::ParticleStore& shown = far.particles();
    for (std::size_t i = 0; i < shown.size(); i += 97) {
        EXPECT_EQ(shown.position.x[i], float(double(a.position.x[i]) + 10000.0));
        EXPECT_EQ(shown.position.y[i], a.position.y[i]);
    }
}

// Scripts read and write world coordinates. Reading the arrays every frame
// changes nothing (a far position shown as a world float is rounded, so only
// the positions a script changed are written back); a changed one and an
// added particle land where they were put.
TEST(FarFromTheOrigin, ScriptsReadAndWriteWorldCoordinates) {
    const pbf::WorldDef def = tankAt(10000.0f);
    pbf::World untouched(def);
    pbf::World read(def);
    for (int frame = 0; frame < 5; ++frame) {
        pbf::test::stepFrame(untouched);
        read.arraysById();
        pbf::test::stepFrame(read);
    }
    const pbf::WorldState stateUntouched = untouched.captureState();
    const pbf::ParticleStore& a = stateUntouched.particles;
    const pbf::WorldState stateRead = read.captureState();
    const pbf::ParticleStore& b = stateRead.particles;
    EXPECT_EQ(a.position.x, b.position.x);
    EXPECT_EQ(a.position.y, b.position.y);

    pbf::ParticleArrays& arrays = read.arraysById();
    const pbf::Vec3 moved{10000.1f, 0.3f, 10000.2f};
    (*arrays.position)[0] = moved.x;
    (*arrays.position)[1] = moved.y;
    (*arrays.position)[2] = moved.z;
    const pbf::Vec3 added{10000.25f, 0.35f, 10000.05f};
    read.addParticles(std::vector<pbf::Vec3>{added}, std::vector<pbf::Vec3>{{}});
    const pbf::LocalFrame& frame = read.localFrame();
    const pbf::ParticleStore state = read.captureState().particles;
    for (std::size_t i = 0; i < state.size(); ++i) {
        if (state.id[i] == 0) {
            EXPECT_EQ(state.position.get(i), frame.toFrame(moved));
        }
        if (state.id[i] == state.size() - 1) {
            EXPECT_EQ(state.position.get(i), frame.toFrame(added));
        }
    }
    const pbf::ParticleArrays& shown = read.arraysById();
    EXPECT_EQ((*shown.position)[3 * (shown.count - 1)], added.x);
    EXPECT_EQ((*shown.position)[0], moved.x);
}

// A scene with every kind of placed thing (a plane, a sphere, a cylinder, a
// mesh, box and sphere bodies, an emitter), written at the origin and 10 km
// away (every coordinate in the file moved): a position the frame missed
// would put its object kilometres from the water. Each solid takes lattice
// sites out of the block, the emitter adds particles, the bodies fall into
// the water.
std::string sceneAt(double x0, double y0, double z0) {
    // Multiples of 1/64 m: exact floats at 30 km too, so the two files
    // describe the same scene to the bit.
    const auto at = [&](double x, double y, double z) {
        const auto q = [](double v) { return std::round(v * 64.0) / 64.0; };
        return fmt::format("[{:.6f}, {:.6f}, {:.6f}]", x0 + q(x), y0 + q(y), z0 + q(z));
    };
    return fmt::format(
        R"({{"name": "far_scene", "particle_radius": 0.02,
        "domain": {{"min": {}, "max": {}}},
        "fluid_blocks": [{{"min": {}, "max": {}}}],
        "solids": [
          {{"type": "plane", "point": {}, "normal": [0, 1, 0]}},
          {{"type": "sphere", "center": {}, "radius": 0.08}},
          {{"type": "cylinder", "base": {}, "axis": [0, 1, 0], "radius": 0.04, "height": 0.5}},
          {{"type": "mesh", "file": "{}", "scale": 0.02, "translation": {}}}],
        "rigid_bodies": [
          {{"type": "box", "min": {}, "max": {}, "density": 500, "rotation": [0, 20, 0]}},
          {{"type": "sphere", "center": {}, "radius": 0.05, "density": 800}}],
        "emitters": [{{"position": {}, "direction": [0, -1, 0], "radius": 0.04, "speed": 1}}],
        "output": {{"fps": 30}}}})",
        at(0, 0, 0), at(1.0, 0.8, 0.4), at(0, 0, 0), at(0.5, 0.5, 0.4), at(0, 0.03, 0),
        at(0.15, 0.35, 0.2), at(0.08, 0, 0.08), pbf::test::scenePath("assets/bunny.obj"),
        at(0.38, 0.03, 0.2), at(0.7, 0.5, 0.1), at(0.8, 0.6, 0.2), at(0.85, 0.3, 0.3),
        at(0.8, 0.7, 0.2));
}

TEST(FarFromTheOrigin, EverySolidBodyAndEmitterOfAFarSceneIsWhereItsFileSays) {
    const pbf::Vec3 offset{10000.0f, 2000.0f, -30000.0f};
    pbf::World here(pbf::parseScene(sceneAt(0, 0, 0), "here.json"));
    pbf::World far(pbf::parseScene(sceneAt(offset.x, offset.y, offset.z), "far.json"));
    ASSERT_TRUE(far.localFrame().shifted());
    EXPECT_GT(here.skippedParticles(), 0u);
    EXPECT_EQ(far.skippedParticles(), here.skippedParticles());
    EXPECT_EQ(far.particleCount(), here.particleCount());
    // Eight frames: the bodies fall into the water (later the splash is
    // chaotic: the same scene moved by 3 m differs by centimetres at
    // frame 15, by 0.03 mm at frame 8).
    for (int frame = 0; frame < 8; ++frame) {
        pbf::test::stepFrame(here);
        pbf::test::stepFrame(far);
    }
    EXPECT_EQ(far.particleCount(), here.particleCount());  // the emitter poured into the domain
    const pbf::StateStatistics s = far.report().state;
    EXPECT_EQ(s.escaped, 0u);
    EXPECT_EQ(s.insideSolid, 0u);
    // Compared in the frame plus its origin, in double: world floats at
    // 30 km are 2 mm apart.
    const pbf::Vec3 o = far.localFrame().origin;
    const auto farWorld = [&](const pbf::Vec3& local) {
        return pbf::Vec3{float(double(local.x) + double(o.x) - double(offset.x)),
                         float(double(local.y) + double(o.y) - double(offset.y)),
                         float(double(local.z) + double(o.z) - double(offset.z))};
    };
    const pbf::WorldState a = here.captureState(), b = far.captureState();
    pbf::Vec3 meanHere, meanFar;
    for (std::size_t i = 0; i < a.particles.size(); ++i) {
        meanHere += a.particles.position.get(i) * (1.0f / float(a.particles.size()));
        meanFar += farWorld(b.particles.position.get(i)) * (1.0f / float(a.particles.size()));
    }
    EXPECT_LT(length(meanFar - meanHere), 1e-4f);
    for (std::size_t k = 0; k < a.bodies.size(); ++k)
        EXPECT_LT(length(farWorld(b.bodies[k].position) - a.bodies[k].position), 1e-4f)
            << "body " << k;
    // The mesh is placed by its pose (the analytic solids by their numbers).
    const pbf::Vec3 mesh = far.solidMotion(3).pose.position;
    EXPECT_LT(length(pbf::Vec3{float(double(mesh.x) - offset.x), float(double(mesh.y) - offset.y),
                               float(double(mesh.z) - offset.z)} -
                     here.solidMotion(3).pose.position),
              1e-6f);
}

}  // namespace
