// pbf::World: definitions built in code, live settings, particles read and
// written by id, particles added at run time, errors as values.
#include "pbf/world/world.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>

#include "pbf/core/solver_constants.hpp"
#include "pbf/io/scene.hpp"
#include "support/reliability_util.hpp"
#include "support/test_util.hpp"

namespace {

using pbf::Vec3;
using pbf::test::stepFrame;

// A tank with one block of water, built in code with the documented defaults.
pbf::WorldDef tank() {
    pbf::WorldDef def;
    def.name = "tank";
    def.simulation.domain = {{0, 0, 0}, {0.4f, 0.4f, 0.4f}};
    def.simulation.particleRadius = 0.02f;
    def.fluidBlocks.push_back({{{0, 0, 0}, {0.2f, 0.3f, 0.4f}}, {}});
    return def;
}

bool sameBits(const std::vector<float>& a, const std::vector<float>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

TEST(World, BuiltInCodeFromADefinition) {
    pbf::World world(tank());
    EXPECT_EQ(world.particleCount(), 5u * 7u * 10u);  // lattice spacing 2 r = 0.04 m
    EXPECT_EQ(world.frame(), 0);
    const pbf::FrameReport r = stepFrame(world);
    EXPECT_EQ(r.frame, 1);
    EXPECT_NEAR(world.time(), 1.0 / 30.0, 1e-12);
    EXPECT_GT(r.substeps, 0);
    EXPECT_GT(r.state.kineticEnergy, 0.0);  // the column started to collapse
}

// Surface tension is an explicit force: its capillary time step is a limit
// of stability and must win over solver.max_substeps. Catches the floor
// frame / max_substeps applied after the capillary limit: then this 0.25 mm
// lattice takes 10 substeps of 1 ms (about 30 times the limit) and the
// cohesion flings particles off at tens of m/s (what stopped
// `pbf validate wetting` at full resolution).
TEST(World, CapillaryTimeStepOverridesMaxSubsteps) {
    pbf::WorldDef def;
    def.name = "capillary";
    def.simulation.domain = {{-0.004f, 0.0f, -0.004f}, {0.004f, 0.008f, 0.004f}};
    def.simulation.particleRadius = 0.000125f;
    def.simulation.fluid.surfaceTension = 0.0728f;
    def.simulation.solver.maxSubsteps = 10;
    def.fps = 100.0f;
    def.fluidBlocks.push_back({{{-0.00075f, 0.0f, -0.00075f}, {0.00075f, 0.0015f, 0.00075f}}, {}});
    pbf::World world(def);
    ASSERT_EQ(world.particleCount(), 216u);
    const double capillary = pbf::SolverConstants::from(def.simulation).capillaryTimeStep;
    ASSERT_LT(capillary, 0.01 / 10);  // the cap alone would allow a longer substep
    for (int frame = 0; frame < 3; ++frame) {
        const pbf::FrameReport r = stepFrame(world);
        EXPECT_GE(r.substeps, int(std::ceil(0.01 / capillary - 1e-6))) << frame;
        EXPECT_LT(r.state.maxSpeed, 3.0) << frame;
    }
}

TEST(World, InvalidDefinitionsNameTheField) {
    pbf::WorldDef outside = tank();
    outside.fluidBlocks[0].box.max.x = 0.5f;
    try {
        pbf::World world(outside);
        FAIL() << "a block outside the domain was accepted";
    } catch (const pbf::SceneError& e) {
        EXPECT_NE(
            std::string(e.what()).find("tank: fluid_blocks[0].min: the block must lie inside"),
            std::string::npos)
            << e.what();
    }
    pbf::WorldDef badEmitter = tank();
    badEmitter.emitters.push_back({});
    badEmitter.emitters[0].position = {0.3f, 0.3f, 0.3f};
    badEmitter.emitters[0].speed = 0.0f;
    EXPECT_EQ(pbf::validate(badEmitter), "emitters[0].speed: must be positive");
    pbf::WorldDef fps = tank();
    fps.fps = 0.0f;
    EXPECT_EQ(pbf::validate(fps), "output.fps: must be in (0, 10000]");
    // NaN in a fluid block (the Python module passes floats as given).
    pbf::WorldDef nan = tank();
    nan.fluidBlocks[0].box.min.y = std::numeric_limits<float>::quiet_NaN();
    EXPECT_EQ(pbf::validate(nan), "fluid_blocks[0].min: must be finite");
    EXPECT_THROW(pbf::World{nan}, pbf::SceneError);
}

// The iteration count is observed in the solver's work (the passes it ran,
// counted in its loop) and in the physics (more iterations, less compression),
// not read back from the settings.
TEST(World, ChangedIterationsChangeTheSolversWork) {
    const pbf::test::ThreadCountScope oneThread(1);
    pbf::World one(tank());
    pbf::World many(tank());
    for (int f = 0; f < 3; ++f) {  // the column is collapsing: the constraint is active
        stepFrame(one);
        stepFrame(many);
    }
    pbf::SimulationParams settings = one.settings();
    settings.solver.iterations = 1;
    one.applySettings(settings);
    settings.solver.iterations = 8;
    many.applySettings(settings);
    const pbf::FrameReport a = stepFrame(one);
    const pbf::FrameReport b = stepFrame(many);
    EXPECT_EQ(a.stageMs.iterations, 1.0 * a.substeps);
    EXPECT_EQ(b.stageMs.iterations, 8.0 * b.substeps);
    EXPECT_EQ(b.iterations, 8);
    EXPECT_LT(b.state.averageDensityError, 0.5 * a.state.averageDensityError);
    EXPECT_LT(b.state.maxDensityError, a.state.maxDensityError);
}

TEST(World, InvalidOrStructuralSettingsAreRefusedAndChangeNothing) {
    const pbf::test::ThreadCountScope oneThread(1);
    pbf::World world(tank());
    pbf::World untouched(tank());
    pbf::SimulationParams bad = world.settings();
    bad.solver.iterations = 0;
    try {
        world.applySettings(bad);
        FAIL() << "iterations 0 accepted";
    } catch (const pbf::SceneError& e) {
        EXPECT_NE(std::string(e.what()).find("solver.iterations: must be in [1, 100], got 0"),
                  std::string::npos)
            << e.what();
    }
    pbf::SimulationParams radius = world.settings();
    radius.particleRadius *= 2.0f;
    try {
        world.applySettings(radius);
        FAIL() << "a new particle radius accepted";
    } catch (const pbf::SceneError& e) {
        EXPECT_NE(std::string(e.what()).find("particle_radius: cannot change"), std::string::npos);
    }
    // Nothing changed: the world steps exactly as one never touched.
    for (int f = 0; f < 2; ++f) {
        stepFrame(world);
        stepFrame(untouched);
    }
    EXPECT_TRUE(sameBits(world.particles().position.y, untouched.particles().position.y));
}

// Writes to the id-ordered arrays reach the solver at the next step; reads
// follow the simulation after every frame.
TEST(World, ArraysByIdAreViewsOfTheParticles) {
    const pbf::test::ThreadCountScope oneThread(1);
    pbf::World world(tank());
    pbf::ParticleArrays& a = world.arraysById();
    ASSERT_EQ(a.count, world.particleCount());
    for (std::uint32_t k = 0; k < a.count; ++k) ASSERT_EQ((*a.id)[k], k);
    // Throw particle 7 up from the far corner of the tank.
    const std::uint32_t id = 7;
    (*a.position)[3 * id + 0] = 0.35f;
    (*a.position)[3 * id + 1] = 0.3f;
    (*a.position)[3 * id + 2] = 0.35f;
    (*a.velocity)[3 * id + 1] = 1.0f;
    const std::vector<float>* buffer = a.position.get();
    stepFrame(world);
    EXPECT_EQ(a.position.get(), buffer);  // same particles: the same buffer, refreshed
    // Ballistic over one frame: y = 0.3 + v t - g t^2 / 2.
    const double t = 1.0 / 30.0;
    EXPECT_NEAR((*a.position)[3 * id + 1], 0.3 + t - 0.5 * 9.81 * t * t, 2e-3);
    EXPECT_NEAR((*a.position)[3 * id + 0], 0.35, 1e-5);
    // The memory-order store agrees.
    const pbf::ParticleStore& p = world.particles();
    for (std::size_t i = 0; i < p.size(); ++i) {
        if (p.id[i] == id) {
            EXPECT_EQ(p.position.y[i], (*a.position)[3 * id + 1]);
        }
    }
}

TEST(World, ParticlesAddedAtRunTimeGetTheNextIds) {
    pbf::World world(tank());
    const std::size_t before = world.particleCount();
    const std::vector<Vec3> x{{0.3f, 0.35f, 0.2f}, {0.3f, 0.35f, 0.25f}};
    const std::vector<Vec3> v{{0, -1, 0}, {0, -1, 0}};
    const std::shared_ptr<std::vector<float>> old = world.arraysById().position;
    world.addParticles(x, v);
    EXPECT_EQ(world.particleCount(), before + 2);
    const pbf::ParticleArrays& a = world.arraysById();
    EXPECT_EQ(a.count, before + 2);
    EXPECT_NE(a.position, old);  // new buffers; views of the old ones stay valid
    EXPECT_EQ(old->size(), 3 * before);
    EXPECT_EQ((*a.position)[3 * before + 2], 0.2f);
    EXPECT_EQ((*a.velocity)[3 * (before + 1) + 1], -1.0f);
    stepFrame(world);
    EXPECT_LT((*a.position)[3 * before + 1], 0.35f);  // falling
    EXPECT_THROW(world.addParticles(x, {}), std::invalid_argument);
}

}  // namespace

// A distributed start: each rank creates a range of the lattice sites and
// numbers its particles after the ranges before it. The ranges, cut
// anywhere (mid-row, mid-block, empty), must give the one-process particles
// with the one-process ids, solids leaving the same sites empty. Catches a
// range that restarts a block's rows at its own first site, skips or
// repeats the site at a cut, or counts a rejected site.
TEST(World, LatticeRangesConcatenateToTheWholeLattice) {
    pbf::WorldDef def = tank();
    def.fluidBlocks.push_back({{{0.24f, 0.0f, 0.0f}, {0.4f, 0.12f, 0.2f}}, {0.5f, 0.0f, 0.0f}});
    pbf::SolidDescription sphere;
    sphere.kind = pbf::SolidDescription::Kind::Sphere;
    sphere.center = {0.1f, 0.1f, 0.2f};
    sphere.radius = 0.09f;
    def.solids.push_back(sphere);
    const auto solids = pbf::buildSolids(def);
    std::size_t skipped = 0;
    const pbf::ParticleStore whole = pbf::createParticles(def, solids.get(), &skipped);
    const std::uint64_t sites = pbf::countParticles(def);
    ASSERT_GT(skipped, 0u);
    ASSERT_EQ(whole.size() + skipped, sites);
    for (const std::vector<std::uint64_t>& cuts : {std::vector<std::uint64_t>{0, sites},
                                                   {0, 7, 7, 351, 352, sites},
                                                   {0, 1, 2, sites / 3, sites - 1, sites}}) {
        pbf::ParticleStore joined;
        std::size_t skippedInAll = 0;
        for (std::size_t k = 0; k + 1 < cuts.size(); ++k) {
            std::size_t skippedHere = 0;
            const pbf::ParticleStore part =
                pbf::createParticles(def, solids.get(), &skippedHere, {}, cuts[k], cuts[k + 1]);
            skippedInAll += skippedHere;
            for (std::size_t i = 0; i < part.size(); ++i) {
                EXPECT_EQ(part.id[i], i);
                joined.add(part.position.get(i), part.velocity.get(i), part.density[i]);
            }
        }
        EXPECT_EQ(skippedInAll, skipped);
        ASSERT_EQ(joined.size(), whole.size());
        EXPECT_EQ(joined.id, whole.id);
        EXPECT_TRUE(sameBits(joined.position.x, whole.position.x));
        EXPECT_TRUE(sameBits(joined.position.y, whole.position.y));
        EXPECT_TRUE(sameBits(joined.position.z, whole.position.z));
        EXPECT_TRUE(sameBits(joined.velocity.x, whole.velocity.x));
    }
}
