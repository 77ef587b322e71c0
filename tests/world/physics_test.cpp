// Physics against closed forms and conservation laws.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "pbf/backend/statistics.hpp"
#include "pbf/io/scene.hpp"
#include "pbf/world/world.hpp"
#include "support/test_util.hpp"
#include "support/wall_check.hpp"

namespace {

using pbf::Vec3;
using pbf::test::stepFrame;

// One fixed solver step of `dt` per frame.
void useFixedSteps(pbf::WorldDef& def, double dt) {
    def.fps = static_cast<float>(1.0 / dt);
    def.simulation.solver.timeStepMode = pbf::TimeStepMode::Fixed;
    def.simulation.solver.fixedSubsteps = 1;
}

// One particle in a large empty box: symplectic Euler (v += g dt; x += v dt)
// gives x_n = x0 + v0 t + g dt^2 n (n + 1) / 2 exactly, which tends to the
// closed form x0 + v0 t + g t^2 / 2 as dt -> 0.
TEST(Physics, FreeFallMatchesClosedForm) {
    pbf::WorldDef def;
    def.simulation.domain = {{-5, -5, -5}, {5, 5, 5}};
    const float r = def.simulation.particleRadius = 0.05f;
    // A block one lattice site wide: one particle at the origin.
    def.fluidBlocks.push_back({{{-r, -r, -r}, {r, r, r}}, {1.0f, 2.0f, 0.0f}});
    def.fps = 1.0f;  // one frame of t = 1 s ...
    def.simulation.solver.timeStepMode = pbf::TimeStepMode::Fixed;
    const Vec3 g = def.simulation.gravity;
    for (const int steps : {10, 100, 1000}) {
        def.simulation.solver.fixedSubsteps = steps;  // ... in `steps` equal steps
        pbf::World world(def);
        ASSERT_EQ(world.particleCount(), 1u);
        const double t = 1.0, dt = t / steps;
        const pbf::FrameReport report = stepFrame(world);
        EXPECT_EQ(report.substeps, steps);
        const pbf::ParticleStore& p = world.particles();
        // PBF derives v = (x* - x) / dt from float positions, so each step
        // adds about one rounding of |x| / dt to v: the tolerance grows with
        // the step count (1e-4 relative at 100 steps).
        const double rounding = 1e-6 * steps;
        const double discreteY = 2.0 * t + g.y * dt * dt * steps * (steps + 1) / 2.0;
        EXPECT_NEAR(p.position.y[0], discreteY, rounding * std::fabs(discreteY) + 1e-5)
            << steps << " steps";
        EXPECT_NEAR(p.position.x[0], 1.0 * t, rounding + 1e-5);
        EXPECT_NEAR(p.velocity.y[0], 2.0 + g.y * t, rounding * 10.0 + 1e-4);
        const double closedY = 2.0 * t + 0.5 * g.y * t * t;
        // The discretisation error is g t dt / 2.
        EXPECT_NEAR(p.position.y[0], closedY,
                    0.5 * std::fabs(g.y) * t * dt * 1.01 + rounding * 3.0 + 1e-4);
    }
}

struct Settled {
    pbf::StateStatistics start;
    pbf::StateStatistics end;
    double peakKineticEnergy = 0.0;
    double initialHeight = 0.0;
    double finalHeight = 0.0;
    double finalMedianSpeed = 0.0;
    double finalSpeed99 = 0.0;    // 99th percentile
    pbf::test::WallLayers walls;  // at the end
};

double meanHeight(const pbf::ParticleStore& p) {
    double sum = 0.0;
    for (float y : p.position.y) sum += y;
    return sum / double(p.size());
}

// A block resting on the floor of a box, simulated for `seconds`.
Settled settleTank(double seconds) {
    const std::string json = R"({
      "domain": {"min": [0, 0, 0], "max": [0.3, 0.4, 0.3]},
      "particle_radius": 0.01,
      "fluid_blocks": [{"min": [0, 0, 0], "max": [0.3, 0.16, 0.3]}],
      "output": {"fps": 30}})";
    pbf::World sim(pbf::parseScene(json, "tank.json"));
    Settled s;
    s.start = sim.report().state;
    // The column's centre of mass is at H/2 for a uniform column of height H.
    s.initialHeight = 2.0 * meanHeight(sim.particles());
    while (sim.time() < seconds) {
        const pbf::FrameReport r = stepFrame(sim);
        s.peakKineticEnergy = std::max(s.peakKineticEnergy, r.state.kineticEnergy);
    }
    s.end = sim.report().state;
    s.finalHeight = 2.0 * meanHeight(sim.particles());
    s.walls = pbf::test::wallLayers(sim.particles(), sim.settings());
    std::vector<float> speeds;
    for (std::size_t i = 0; i < sim.particles().size(); ++i)
        speeds.push_back(pbf::length(sim.particles().velocity.get(i)));
    std::sort(speeds.begin(), speeds.end());
    s.finalMedianSpeed = speeds[speeds.size() / 2];
    s.finalSpeed99 = speeds[speeds.size() * 99 / 100];
    return s;
}

TEST(Physics, RestingTankKeepsVolumeAndComesToRest) {
    const Settled s = settleTank(3.0);
    std::printf(
        "resting tank: fullest wall layer %.3f of one lattice layer (%s), closest pair "
        "on a wall %.4f m\n",
        s.walls.worstFill, s.walls.worstWall.c_str(), s.walls.closestPair);
    // Nothing pressed into the walls: the floor holds its one lattice layer
    // (measured 1.009, closest pair 0.83 spacings). Checked that this can
    // fail: without the walls' density term the floor layer holds 1.41 and
    // pairs come within 0.53 spacings; with the walls' gradient term reversed
    // it holds 1.049.
    EXPECT_LT(s.walls.worstFill, 1.03) << s.walls.worstWall;
    EXPECT_GT(s.walls.closestPair, 0.7 * 0.02) << "m: particles stacked on a wall";
    EXPECT_LT(s.end.averageDensityError, 0.01) << "average compression after settling";
    // Volume (height x base) preserved within a few percent.
    EXPECT_NEAR(s.finalHeight / s.initialHeight, 1.0, 0.03)
        << "initial " << s.initialHeight << " final " << s.finalHeight;
    // Kinetic energy decays towards zero: far below its peak; what is left is
    // millimetre-per-second solver noise (PBF's residual of each step's g dt).
    EXPECT_LT(s.end.kineticEnergy, 0.1 * s.peakKineticEnergy);
    EXPECT_LT(s.finalMedianSpeed, 0.02) << "m/s";
    EXPECT_LT(s.finalSpeed99, 0.08) << "m/s";
}

// Without gravity or walls, PBF's position corrections come in equal and
// opposite pairs (lambda_i + lambda_j, antisymmetric gradient) and XSPH uses a
// symmetric volume, so total momentum is conserved to rounding.
TEST(Physics, IsolatedBlobConservesLinearMomentum) {
    const std::string json = R"({
      "domain": {"min": [-5, -5, -5], "max": [5, 5, 5]},
      "gravity": [0, 0, 0],
      "particle_radius": 0.02,
      "fluid": {"viscosity": 0.05},
      "fluid_blocks": [{"min": [-0.2, -0.2, -0.2], "max": [0.2, 0.2, 0.2]}]})";
    pbf::Scene scene = pbf::parseScene(json, "blob.json");
    useFixedSteps(scene, 1.0 / 240.0);
    pbf::World world(scene);
    // Random velocities and a compressed lattice so the constraint is active,
    // written through the id-ordered arrays (as a script would).
    pbf::ParticleArrays& a = world.arraysById();
    std::mt19937 rng(6);
    std::normal_distribution<float> speed(0.0f, 0.5f);
    for (std::size_t k = 0; k < 3 * a.count; ++k) {
        (*a.velocity)[k] = speed(rng);
        (*a.position)[k] *= 0.85f;
    }
    double momentum[3] = {0, 0, 0};
    double scale = 0.0;  // sum of |m v|, the size of the rounding error
    const double mass = world.constants().particleMass;
    for (std::size_t k = 0; k < a.count; ++k) {
        const Vec3 v{(*a.velocity)[3 * k], (*a.velocity)[3 * k + 1], (*a.velocity)[3 * k + 2]};
        for (int axis = 0; axis < 3; ++axis) momentum[axis] += mass * v[axis];
        scale += mass * pbf::length(v);
    }
    // The compressed blob really activates the density constraint.
    EXPECT_GT(stepFrame(world).state.maxDensityError, 0.2);
    for (int k = 1; k < 50; ++k) stepFrame(world);
    const pbf::StateStatistics after = world.report().state;
    for (int axis = 0; axis < 3; ++axis)
        EXPECT_NEAR(after.momentum[axis], momentum[axis], 1e-4 * scale) << "axis " << axis;
}

TEST(Physics, RestLatticeHasRestDensity) {
    // The particle mass is chosen so that an interior particle of the initial
    // lattice has exactly rest density: a resting block starts unstressed.
    const std::string json = R"({
      "domain": {"min": [0, 0, 0], "max": [1, 1, 1]}, "gravity": [0, 0, 0],
      "particle_radius": 0.02,
      "fluid_blocks": [{"min": [0.2, 0.2, 0.2], "max": [0.6, 0.6, 0.6]}]})";
    pbf::Scene scene = pbf::parseScene(json, "lattice.json");
    useFixedSteps(scene, 1e-4);
    pbf::World world(scene);
    stepFrame(world);
    const pbf::ParticleStore& p = world.particles();
    const float centre = 0.4f;
    for (std::size_t i = 0; i < p.size(); ++i) {
        const Vec3 x = p.position.get(i);
        if (std::fabs(x.x - centre) < 0.05f && std::fabs(x.y - centre) < 0.05f &&
            std::fabs(x.z - centre) < 0.05f) {
            EXPECT_NEAR(p.density[i], 1000.0f, 1.0f);
        }
    }
}

TEST(Physics, DamBreakNeverExplodesAndNothingIsPressedIntoTheWalls) {
    // Coarse dam break through the impact on the far wall with adaptive substeps.
    pbf::Scene scene = pbf::loadScene(pbf::test::scenePath("dam_break.json"),
                                      {pbf::parseOverride("particle_radius=0.02")});
    pbf::World sim(scene);
    double maxSpeed = 0.0;
    double worstFill = 0.0;
    double closestPair = 1e30;
    while (sim.time() < 1.5) {
        const pbf::FrameReport r = stepFrame(sim);
        maxSpeed = std::max(maxSpeed, r.state.maxSpeed);
        const pbf::test::WallLayers walls = pbf::test::wallLayers(sim.particles(), sim.settings());
        worstFill = std::max(worstFill, walls.worstFill);
        closestPair = std::min(closestPair, walls.closestPair);
    }
    std::printf(
        "dam break: fullest wall layer %.3f of one lattice layer, closest pair on a wall "
        "%.4f m\n",
        worstFill, closestPair);
    // The impact presses water against the far wall, but never more than
    // one lattice layer's worth onto it, and never stacked (measured 0.95 and
    // 0.33 spacings; without the walls' density term 1.33 and 0.22, with
    // their gradient reversed 1.22). The closest pair is one pair over the
    // whole run, so it moves with the rounding of the sums: 0.46 spacings
    // with the cells' rows along x, 0.33 along z (the key's order since).
    EXPECT_LT(worstFill, 1.1);
    EXPECT_GT(closestPair, 0.3 * 0.04) << "m";
    // A column of height H = 0.7 m cannot produce speeds far beyond sqrt(2 g H) ~ 3.7 m/s.
    EXPECT_LT(maxSpeed, 2.0 * std::sqrt(2.0 * 9.81 * 0.7));
    EXPECT_LT(sim.report().state.averageDensityError, 0.05);
}

}  // namespace
