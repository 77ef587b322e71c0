// Bit-identical particle state: 1 vs 2 threads, compact vs wide neighbour lists.
#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include "pbf/core/threading.hpp"
#include "pbf/io/scene.hpp"
#include "pbf/world/world.hpp"
#include "support/test_util.hpp"

namespace {

// A coarse dam break with vorticity confinement on (every pass runs), one
// fixed step of 1/240 s per frame.
pbf::Scene coarseDamBreak(const std::vector<std::string>& extra = {}) {
    std::vector<pbf::SceneOverride> overrides{
        pbf::parseOverride("particle_radius=0.02"), pbf::parseOverride("fluid.vorticity=0.05"),
        pbf::parseOverride("output.fps=240"), pbf::parseOverride("solver.time_step=fixed"),
        pbf::parseOverride("solver.substeps=1")};
    for (const std::string& e : extra) overrides.push_back(pbf::parseOverride(e));
    return pbf::loadScene(pbf::test::scenePath("dam_break.json"), overrides);
}

// `steps` solver steps on `threads` threads, the CPU backend's neighbour
// lists compact (16-bit) when their span allows or forced wide (32-bit).
pbf::ParticleStore runSteps(int threads, int steps, std::uint32_t compactListSpan = 65536,
                            const std::vector<std::string>& extra = {}) {
    pbf::setThreadCount(threads);
    pbf::WorldOptions options;
    options.backendOptions.compactListSpan = compactListSpan;
    pbf::World world(coarseDamBreak(extra), options);
    for (int k = 0; k < steps; ++k) pbf::test::stepFrame(world);
    return world.particles();
}

bool bitEqual(const std::vector<float>& a, const std::vector<float>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

void expectIdenticalBits(const pbf::ParticleStore& a, const pbf::ParticleStore& b) {
    ASSERT_EQ(a.size(), b.size());
    EXPECT_EQ(a.id, b.id);
    EXPECT_TRUE(bitEqual(a.position.x, b.position.x));
    EXPECT_TRUE(bitEqual(a.position.y, b.position.y));
    EXPECT_TRUE(bitEqual(a.position.z, b.position.z));
    EXPECT_TRUE(bitEqual(a.velocity.x, b.velocity.x));
    EXPECT_TRUE(bitEqual(a.velocity.y, b.velocity.y));
    EXPECT_TRUE(bitEqual(a.velocity.z, b.velocity.z));
    EXPECT_TRUE(bitEqual(a.density, b.density));
}

TEST(Determinism, OneAndTwoThreadsGiveIdenticalBits) {
    const pbf::ParticleStore one = runSteps(1, 100);
    const pbf::ParticleStore two = runSteps(2, 100);
    pbf::setThreadCount(pbf::hardwareThreadCount());
    expectIdenticalBits(one, two);
    // The run moved: the test compares a real flow, not a frozen state.
    EXPECT_NE(one.position.x,
              pbf::createParticles(pbf::loadScene(pbf::test::scenePath("dam_break.json"),
                                                  {pbf::parseOverride("particle_radius=0.02")}))
                  .position.x);
}

TEST(Determinism, CompactAndWideNeighbourListsGiveIdenticalBits) {
    // Same neighbours in the same order, so the same arithmetic.
    const pbf::ParticleStore compact = runSteps(2, 60, 65536);
    const pbf::ParticleStore wide = runSteps(2, 60, 16);
    pbf::setThreadCount(pbf::hardwareThreadCount());
    expectIdenticalBits(compact, wide);
}

// The accuracy options (docs/performance.md, "Accuracy per cost"): the
// tolerance's stopping test sums the blocks' compression in block order,
// and the warm start's acceleration is a per-particle array permuted with
// the particles, so thread count changes nothing. Checked that this can
// fail: summing the blocks' compression through an OpenMP reduction
// changed the iteration count of some steps between 1 and 2 threads.
TEST(Determinism, AccuracyOptionsGiveIdenticalBitsOnOneAndTwoThreads) {
    const std::vector<std::string> options{"solver.max_density_error=0.002",
                                           "solver.min_iterations=1", "solver.max_iterations=50",
                                           "solver.over_relaxation=1.2", "solver.warm_start=0.8"};
    const pbf::ParticleStore one = runSteps(1, 100, 65536, options);
    const pbf::ParticleStore two = runSteps(2, 100, 65536, options);
    pbf::setThreadCount(pbf::hardwareThreadCount());
    expectIdenticalBits(one, two);
    EXPECT_EQ(one.solveAcceleration.x, two.solveAcceleration.x);
    EXPECT_EQ(one.solveAcceleration.y, two.solveAcceleration.y);
    ASSERT_EQ(one.solveAcceleration.x.size(), one.size()) << "the warm start kept nothing";
}

// Surface tension (the cohesion's SIMD pass reads x* and the densities of
// the neighbours, the curvature force's four passes each the previous
// pass's field, and both write each particle's velocity) with adhesion on
// the domain walls: the dam break's surface particles pull, and the floor and
// walls pull back. The coarse dam break's spacing makes the capillary time
// step long, so the fixed 1/240 s steps are within it.
TEST(Determinism, SurfaceTensionGivesIdenticalBitsOnOneAndTwoThreads) {
    const std::vector<std::string> options{"fluid.surface_tension=0.0728",
                                           "solver.wall_adhesion=0.6"};
    const pbf::ParticleStore one = runSteps(1, 80, 65536, options);
    const pbf::ParticleStore two = runSteps(2, 80, 65536, options);
    const pbf::ParticleStore off = runSteps(2, 80, 65536);
    pbf::setThreadCount(pbf::hardwareThreadCount());
    expectIdenticalBits(one, two);
    // Surface tension changed the flow (the pass ran).
    EXPECT_NE(one.position.x, off.position.x);
}

}  // namespace
