// The surface layer's strands (equations.hpp, "Strands"): a surface
// particle whose neighbourhood is narrower than the kernel in two
// directions leaves the surface layer, so that a neck thinner than the
// particles lets go. Shapes cut from the rest lattice keep every particle
// (a flat face, a 90-degree edge and a corner are resolved, and so is a
// sheet one particle thick: one thin direction only); a chain and a strand
// two particles across, packed as a thinning neck packs it, are strands; a
// wall within reach holds a strand.
#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <vector>

#include "backend/reference/equations.hpp"
#include "backend/reference/neighbor_grid.hpp"
#include "backend/reference/particle_sums.hpp"
#include "pbf/core/params.hpp"
#include "pbf/core/solver_constants.hpp"

namespace pbf::test {
namespace {

const Aabb kDomain{{-0.05f, -0.05f, -0.05f}, {0.05f, 0.05f, 0.05f}};

SolverConstants waterConstants(const Aabb& domain = kDomain) {
    SimulationParams p;
    p.domain = domain;
    p.particleRadius = 0.00025f;  // 0.5 mm spacing, as the validation's drops
    p.fluid.surfaceTension = 0.0728f;
    return SolverConstants::from(p);
}

// Sites (a, b, k) x `step` for the integer ranges given, offset by `origin`.
std::vector<Vec3> block(float step, int nx, int ny, int nz, const Vec3& origin = {}) {
    std::vector<Vec3> x;
    for (int a = 0; a < nx; ++a)
        for (int b = 0; b < ny; ++b)
            for (int k = 0; k < nz; ++k)
                x.push_back(origin + Vec3{float(a) * step, float(b) * step, float(k) * step});
    return x;
}

// How many particles leave the surface layer, every particle taken to be on
// the surface (density 0): the spread alone decides.
std::size_t strandCount(const SolverConstants& c, const std::vector<Vec3>& x) {
    reference::NeighborGrid grid(c.domain, c.h);
    grid.build(x);
    std::size_t strands = 0;
    for (std::size_t i = 0; i < x.size(); ++i)
        if (reference::surfaceLayer(c, nullptr, x, 0.0f, grid.neighbors(i), i) == 0.0f) ++strands;
    return strands;
}

float spacing(const SolverConstants& c) {
    return std::sqrt(c.cohesionMinDistance2);
}

TEST(SurfaceLayer, TheThresholdIsAStrandOfAboutOneAndAHalfSpacings) {
    const SolverConstants c = waterConstants();
    const float d = spacing(c);
    EXPECT_FLOAT_EQ(c.strandSpread2, 0.16f * d * d);
    EXPECT_FLOAT_EQ(c.strandLength2, 0.26f * d * d);
    EXPECT_EQ(SolverConstants::from(SimulationParams{}).strandSpread2, 0.0f);
}

// Faces, edges and corners of a lattice cube, and the inside.
TEST(SurfaceLayer, ALatticeCubeHasNoStrands) {
    const SolverConstants c = waterConstants();
    EXPECT_EQ(strandCount(c, block(spacing(c), 10, 10, 10)), 0u);
}

// One thin direction is a sheet, not a strand (the middle eigenvalue, not
// the smallest).
TEST(SurfaceLayer, ASheetOneParticleThickIsNotAStrand) {
    const SolverConstants c = waterConstants();
    EXPECT_EQ(strandCount(c, block(spacing(c), 12, 1, 12)), 0u);
}

// A rod three particles across is resolved.
TEST(SurfaceLayer, ARodThreeAcrossIsNotAStrand) {
    const SolverConstants c = waterConstants();
    EXPECT_EQ(strandCount(c, block(spacing(c), 16, 3, 3)), 0u);
}

// A chain's particles are a strand but for its two ends: each sees one
// neighbour, a pair (below).
TEST(SurfaceLayer, AChainIsAStrand) {
    const SolverConstants c = waterConstants();
    const std::vector<Vec3> chain = block(spacing(c), 12, 1, 1);
    EXPECT_EQ(strandCount(c, chain), chain.size() - 2);
}

// Small every way: a drop below the resolution, not a strand. A pair, and a
// clump of eight packed as a satellite drop packs them.
TEST(SurfaceLayer, AClumpOfAFewParticlesIsNotAStrand) {
    const SolverConstants c = waterConstants();
    EXPECT_EQ(strandCount(c, block(0.9f * spacing(c), 2, 1, 1)), 0u);
    EXPECT_EQ(strandCount(c, block(0.8f * spacing(c), 2, 2, 2)), 0u);
}

// Two particles across, packed to 0.7 spacings as a neck that stopped
// thinning is (its particles sit inside one another's flat kernel top); all
// but its end slabs (four particles at each end: short of the kernel along
// it, a clump).
TEST(SurfaceLayer, ANeckTwoParticlesAcrossIsAStrand) {
    const SolverConstants c = waterConstants();
    const std::vector<Vec3> neck = block(0.7f * spacing(c), 20, 2, 2);
    EXPECT_EQ(strandCount(c, neck), neck.size() - 8);
}

// The same chain half a spacing from the domain's floor: the wall holds it.
TEST(SurfaceLayer, AWallWithinReachHoldsAStrand) {
    const SolverConstants c = waterConstants();
    const float d = spacing(c);
    const std::vector<Vec3> chain = block(d, 12, 1, 1, {0.0f, kDomain.min.y + 0.5f * d, 0.0f});
    EXPECT_EQ(strandCount(c, chain), 0u);
    const std::vector<Vec3> away = block(d, 12, 1, 1, {0.0f, 0.0f, 0.0f});
    EXPECT_EQ(strandCount(c, away), away.size() - 2);
}

// A particle inside the water (density at rest) is never in the layer.
TEST(SurfaceLayer, ParticlesInsideTheWaterAreNotInTheLayer) {
    const SolverConstants c = waterConstants();
    const std::vector<Vec3> x = block(spacing(c), 6, 6, 6);
    reference::NeighborGrid grid(c.domain, c.h);
    grid.build(x);
    for (std::size_t i = 0; i < x.size(); ++i) {
        EXPECT_EQ(reference::surfaceLayer(c, nullptr, x, c.restDensity, grid.neighbors(i), i),
                  0.0f);
        EXPECT_EQ(
            reference::surfaceLayer(c, nullptr, x, 0.9f * c.restDensity, grid.neighbors(i), i),
            1.0f);
    }
}

}  // namespace
}  // namespace pbf::test
