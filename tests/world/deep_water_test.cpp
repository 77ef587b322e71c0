// Deep water: a fixed number of Jacobi iterations carries a column's
// support a few layers down per substep, so a column deep in the sense of
// Pi = (depth / spacing) (g dt^2 / spacing) / iterations falls, slams and
// erupts as it starts. The adaptive substep keeps Pi at most
// solver.depth_limit for the depth the blocks start with (World::depthStep).
// The tank: 0.2 m of water at r = 3 mm (33 layers) and the default 1/240 s
// substeps, Pi = 0.24; a narrow slice of it (20 x 4 particles) for speed.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "pbf/io/scene.hpp"
#include "pbf/world/world.hpp"
#include "support/test_util.hpp"

namespace {

constexpr double kDepth = 0.2;  // m

pbf::Scene deepTank(const std::string& solver) {
    return pbf::parseScene(R"({
      "name": "deep",
      "domain": {"min": [0, 0, 0], "max": [0.06, 0.4, 0.024]},
      "particle_radius": 0.003,
      "fluid_blocks": [{"min": [0, 0, 0], "max": [0.06, 0.2, 0.024]}],
      "solver": {)" + solver + R"(},
      "output": {"fps": 60}})",
                           "deep.json");
}

struct Rest {
    double top = 0.0;          // m: the highest particle's centre at the end
    double highest = 0.0;      // m: the highest any particle reached
    double medianSpeed = 0.0;  // m/s at the end
    double compression = 0.0;  // average, at the end
    double substeps = 0.0;     // per frame, over the run
};

Rest settle(const pbf::Scene& scene, double seconds) {
    pbf::World world(scene);
    Rest r;
    int frames = 0;
    while (world.time() < seconds) {
        r.substeps += pbf::test::stepFrame(world).substeps;
        ++frames;
        const pbf::ParticleStore& p = world.particles();
        r.highest = std::max(r.highest,
                             double(*std::max_element(p.position.y.begin(), p.position.y.end())));
    }
    const pbf::ParticleStore& p = world.particles();
    r.top = *std::max_element(p.position.y.begin(), p.position.y.end());
    std::vector<float> speeds;
    for (std::size_t i = 0; i < p.size(); ++i) speeds.push_back(pbf::length(p.velocity.get(i)));
    std::sort(speeds.begin(), speeds.end());
    r.medianSpeed = speeds[speeds.size() / 2];
    r.compression = world.report().state.averageDensityError;
    r.substeps /= frames;
    return r;
}

TEST(DeepWater, TheDepthLimitKeepsADeepColumnFromErupting) {
    const Rest limited = settle(deepTank(""), 1.0);
    const Rest unlimited = settle(deepTank(R"("depth_limit": 0)"), 1.0);
    std::printf(
        "deep column: limited top %.3f m (highest %.3f), median %.3f m/s, compression "
        "%.4f, %.1f substeps per frame; unlimited highest %.3f m, median %.3f m/s, "
        "compression %.4f\n",
        limited.top, limited.highest, limited.medianSpeed, limited.compression, limited.substeps,
        unlimited.highest, unlimited.medianSpeed, unlimited.compression);
    // Without the limit the column erupts: water thrown 10 cm and more above
    // its surface (measured: to the domain's top, 0.4 m, within 0.2 s).
    EXPECT_GT(unlimited.highest, kDepth + 0.1) << "the case must erupt without the limit";
    // With it the water rests (measured: top 0.193-0.197 m, median speed
    // 0.016 m/s after 0.5 s, average compression 1.5 %).
    EXPECT_LT(limited.highest, kDepth + 0.01);
    EXPECT_GT(limited.top, kDepth - 0.012) << "the column lost its volume";
    EXPECT_LT(limited.medianSpeed, 0.03);
    EXPECT_LT(limited.compression, 0.03);
    // 0.006 sqrt(0.1 * 4 / (9.81 * 0.2)) = 2.7 ms: 7 substeps a frame, not 4.
    EXPECT_GE(limited.substeps, 6.5) << "the limit did not shorten the substeps";
}

}  // namespace
