// 1 thread vs 2 threads: bit-identical particle state.
#include <gtest/gtest.h>

#include <cstring>

#include "pbf/scene.hpp"
#include "pbf/simulation.hpp"
#include "pbf/threading.hpp"
#include "test_util.hpp"

namespace {

pbf::ParticleStore runSteps(int threads, int steps) {
    pbf::setThreadCount(threads);
    const pbf::Scene scene = pbf::loadScene(
        pbf::test::scenePath("dam_break.json"),
        {pbf::parseOverride("particle_radius=0.02"), pbf::parseOverride("fluid.vorticity=0.05")});
    pbf::Simulation sim(scene);
    for (int k = 0; k < steps; ++k) sim.solver().step(sim.particles(), 1.0f / 240.0f);
    return sim.particles();
}

// The same steps with the solver alone, its neighbour lists compact (16-bit)
// or forced wide (32-bit).
pbf::ParticleStore runSolver(std::uint32_t compactListSpan, int steps) {
    const pbf::Scene scene = pbf::loadScene(
        pbf::test::scenePath("dam_break.json"),
        {pbf::parseOverride("particle_radius=0.02"), pbf::parseOverride("fluid.vorticity=0.05")});
    pbf::ParticleStore particles = pbf::createParticles(scene);
    pbf::Solver solver(scene.simulation, nullptr, compactListSpan);
    for (int k = 0; k < steps; ++k) solver.step(particles, 1.0f / 240.0f);
    return particles;
}

bool bitEqual(const std::vector<float>& a, const std::vector<float>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

TEST(Determinism, OneAndTwoThreadsGiveIdenticalBits) {
    const pbf::ParticleStore one = runSteps(1, 100);
    const pbf::ParticleStore two = runSteps(2, 100);
    pbf::setThreadCount(pbf::hardwareThreadCount());
    ASSERT_EQ(one.size(), two.size());
    EXPECT_EQ(one.id, two.id);
    EXPECT_TRUE(bitEqual(one.position.x, two.position.x));
    EXPECT_TRUE(bitEqual(one.position.y, two.position.y));
    EXPECT_TRUE(bitEqual(one.position.z, two.position.z));
    EXPECT_TRUE(bitEqual(one.velocity.x, two.velocity.x));
    EXPECT_TRUE(bitEqual(one.velocity.y, two.velocity.y));
    EXPECT_TRUE(bitEqual(one.velocity.z, two.velocity.z));
    EXPECT_TRUE(bitEqual(one.density, two.density));
    // The run moved: the test compares a real flow, not a frozen state.
    EXPECT_NE(one.position.x,
              pbf::createParticles(pbf::loadScene(pbf::test::scenePath("dam_break.json"),
                                                  {pbf::parseOverride("particle_radius=0.02")}))
                  .position.x);
}

TEST(Determinism, CompactAndWideNeighbourListsGiveIdenticalBits) {
    // Same neighbours in the same order, so the same arithmetic.
    const pbf::ParticleStore compact = runSolver(65536, 60);
    const pbf::ParticleStore wide = runSolver(16, 60);
    ASSERT_EQ(compact.size(), wide.size());
    EXPECT_EQ(compact.id, wide.id);
    EXPECT_TRUE(bitEqual(compact.position.x, wide.position.x));
    EXPECT_TRUE(bitEqual(compact.position.y, wide.position.y));
    EXPECT_TRUE(bitEqual(compact.position.z, wide.position.z));
    EXPECT_TRUE(bitEqual(compact.velocity.x, wide.velocity.x));
    EXPECT_TRUE(bitEqual(compact.density, wide.density));
}

}  // namespace
