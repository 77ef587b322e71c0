// A small dam break run by the CPU backend and by the reference backend
// through pbf::World, 50 substeps.
//
// Tolerance: the two backends compute the same maths with different
// rounding (one step differs by about an ulp of the positions: see
// stages_vs_reference_test.cpp), and a splashing flow amplifies any such
// difference: particles at a wall switch between "touching" and "not
// touching" (box clamp, wall response), the constraint's clamp C >= 0 and
// the neighbour lists switch at thresholds. No closed-form bound survives
// that, so the test measures the flow's own sensitivity: a second CPU run
// whose initial positions differ by one ulp. The reference may not drift
// from the CPU run faster than that run does (times 4: two realisations
// of the same amplification differ by up to ~2x, measured), with a floor
// of a few ulps for the first steps. A wrong term (s_corr dropped, say)
// moves particles by ~1e-3 spacings in the first step, 1000 times the
// floor, and fails at once.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "pbf/scene.hpp"
#include "pbf/world.hpp"

namespace pbf::test {
namespace {

// 1080 particles (12 x 15 x 6) collapsing towards a box obstacle, one fixed
// substep of 1/300 s per frame, XSPH and vorticity confinement on: every
// stage of both backends runs.
std::string damBreakJson() {
    return R"({
      "name": "small_dam_break",
      "domain": {"min": [0, 0, 0], "max": [0.6, 0.5, 0.2]},
      "particle_radius": 0.01,
      "fluid": {"viscosity": 0.01, "vorticity": 0.05},
      "fluid_blocks": [{"min": [0, 0, 0], "max": [0.24, 0.3, 0.12]}],
      "solids": [{"type": "box", "min": [0.3, 0, 0.05], "max": [0.34, 0.05, 0.15]}],
      "solver": {"iterations": 4, "time_step": "fixed", "substeps": 1},
      "output": {"fps": 300}
    })";
}

// Largest distance between the same particle (by id) in the two worlds.
double maxPositionDifference(const World& a, const World& b) {
    const ParticleStore& pa = a.particles();
    const ParticleStore& pb = b.particles();
    std::vector<Vec3> byId(pb.size());
    for (std::size_t k = 0; k < pb.size(); ++k) byId[pb.id[k]] = pb.position.get(k);
    double largest = 0.0;
    for (std::size_t k = 0; k < pa.size(); ++k)
        largest = std::max(largest, double(length(pa.position.get(k) - byId[pa.id[k]])));
    return largest;
}

FrameResult step(World& world) {
    FrameResult r = world.stepFrame();
    EXPECT_TRUE(r.ok()) << r.error->message;
    return r;
}

TEST(WorldVsReference, DamBreakAgreesOverFiftySubsteps) {
    const Scene scene = parseScene(damBreakJson(), "small_dam_break");
    World cpu(scene, WorldOptions{BackendKind::Cpu, {}});
    World perturbed(scene, WorldOptions{BackendKind::Cpu, {}});
    World reference(scene, WorldOptions{BackendKind::Reference, {}});
    ASSERT_EQ(cpu.particleCount(), reference.particleCount());
    ASSERT_GT(cpu.particleCount(), 1000u);
    ParticleStore& moved = *perturbed.backend().mutableHostState();
    for (float& x : moved.position.x) x = std::nextafter(x, 1.0f);  // one ulp

    const double spacing = scene.simulation.particleSpacing();
    const double floor = 8.0 * 0x1p-24 * 0.6 / spacing;  // 8 ulps of the largest coordinate
    double referenceDrift = 0.0, perturbedDrift = 0.0;   // largest so far, in spacings
    float farthest = 0.0f;
    std::printf("  substep  max |x_cpu - x_ref|  max |x_cpu - x_cpu'|  (spacings)\n");
    for (int substep = 1; substep <= 50; ++substep) {
        ASSERT_EQ(step(cpu).report.substeps, 1);
        step(perturbed);
        EXPECT_EQ(step(reference).report.iterations, 4);  // counted by the reference's loop
        referenceDrift = std::max(referenceDrift, maxPositionDifference(cpu, reference) / spacing);
        perturbedDrift = std::max(perturbedDrift, maxPositionDifference(cpu, perturbed) / spacing);
        if (substep <= 2 || substep % 10 == 0)
            std::printf("  %7d  %19.3g  %20.3g\n", substep, referenceDrift, perturbedDrift);
        ASSERT_LE(referenceDrift, 4.0 * std::max(perturbedDrift, floor)) << "substep " << substep;
    }
    const ParticleStore& p = reference.particles();
    farthest = *std::max_element(p.position.x.begin(), p.position.x.end());
    // A real flow was compared: the front reached the obstacle.
    EXPECT_GT(cpu.report().state.maxSpeed, 1.0);
    EXPECT_GT(farthest, 0.29f);
    EXPECT_LT(referenceDrift, 0.1);  // and stayed far below anything visible
}

}  // namespace
}  // namespace pbf::test
