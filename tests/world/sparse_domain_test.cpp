// A huge, mostly empty domain costs what its water costs, on every backend:
// the same block of water in a 60 m x 4 m x 60 m basin (1.8e9 cells of the
// kernel radius: a dense cell table would need 7 GB) and in a tight tank
// moves the same and needs about the same memory.
#include <gtest/gtest.h>

#include <cstdio>

#include "pbf/world/world.hpp"
#include "support/test_util.hpp"

namespace {

using pbf::Aabb;
using pbf::BackendKind;

pbf::WorldDef waterIn(const Aabb& domain) {
    pbf::WorldDef def;
    def.name = "sparse";
    def.simulation.domain = domain;
    def.simulation.particleRadius = 0.005f;
    // 12 cm of water on the floor, 29 cm from the nearest walls of the tank
    // (its front, about 2 sqrt(g H) = 2 m/s, does not reach them in 2 frames).
    def.fluidBlocks.push_back({{{0.29f, 0.0f, 0.29f}, {0.41f, 0.12f, 0.41f}}, {}});
    return def;
}

class SparseDomain : public ::testing::TestWithParam<BackendKind> {};

TEST_P(SparseDomain, AHugeEmptyBasinMovesTheWaterAsATightTankAndCostsTheSame) {
    pbf::WorldOptions options;
    options.backend = GetParam();
    pbf::World basin(waterIn({{0, 0, 0}, {60, 4, 60}}), options);
    // The same order of the key's axes as the basin (its shortest side
    // vertical), so that both sort the particles alike.
    pbf::World tight(waterIn({{0, 0, 0}, {0.7f, 0.6f, 0.7f}}), options);
    ASSERT_EQ(basin.particleCount(), tight.particleCount());
    for (int frame = 0; frame < 2; ++frame) {
        pbf::test::stepFrame(basin);
        pbf::test::stepFrame(tight);
    }
    // The same motion, to the bit: the cell key of a cell does not depend on
    // the domain's size (cells are counted from the same corner, the axes
    // ordered by the sides' lengths alike), so both sort the particles alike. Catches anything in the step that scales
    // with the domain (a wall contact tolerance proportional to its extent
    // made every particle within 12 mm of the basin's floor a contact).
    const pbf::ParticleArrays& a = basin.arraysById();
    const pbf::ParticleArrays& b = tight.arraysById();
    double speed2 = 0.0;
    for (float v : *a.velocity) speed2 += double(v) * double(v);
    EXPECT_GT(speed2, 0.01 * double(a.count));  // moving: mean speed over 0.1 m/s
    EXPECT_EQ(*a.position, *b.position);
    EXPECT_EQ(*a.velocity, *b.velocity);
    const double basinBytes = double(basin.backend().diagnostics().memoryBytes);
    const double tightBytes = double(tight.backend().diagnostics().memoryBytes);
    std::printf("  %zu particles: %.0f bytes in the basin, %.0f in the tight tank\n", a.count,
                basinBytes, tightBytes);
    EXPECT_LE(basinBytes, 1.3 * tightBytes + 65536.0);
}

INSTANTIATE_TEST_SUITE_P(Backends, SparseDomain, pbf::test::everyBackendHere(),
                         pbf::test::backendTestName);

}  // namespace
