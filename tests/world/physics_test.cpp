// Physics against closed forms and conservation laws.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "pbf/scene.hpp"
#include "pbf/simulation.hpp"
#include "pbf/solver.hpp"
#include "pbf/statistics.hpp"
#include "support/test_util.hpp"

namespace {

using pbf::Vec3;

// One particle in a large empty box: symplectic Euler (v += g dt; x += v dt)
// gives x_n = x0 + v0 t + g dt^2 n (n + 1) / 2 exactly, which tends to the
// closed form x0 + v0 t + g t^2 / 2 as dt -> 0.
TEST(Physics, FreeFallMatchesClosedForm) {
    pbf::SimulationParams params;
    params.domain = {{-5, -5, -5}, {5, 5, 5}};
    params.particleRadius = 0.05f;
    const Vec3 g = params.gravity;
    for (const int steps : {10, 100, 1000}) {
        pbf::ParticleStore p;
        p.add({0, 0, 0}, {1.0f, 2.0f, 0.0f}, 1000.0f);
        pbf::Solver solver(params);
        const double t = 1.0, dt = t / steps;
        for (int k = 0; k < steps; ++k) solver.step(p, static_cast<float>(dt));
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
    double finalSpeed99 = 0.0;  // 99th percentile
    std::size_t maxEscaped = 0;
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
    pbf::Simulation sim(pbf::parseScene(json, "tank.json"));
    Settled s;
    s.start = sim.report().state;
    // The column's centre of mass is at H/2 for a uniform column of height H.
    s.initialHeight = 2.0 * meanHeight(sim.particles());
    while (sim.time() < seconds) {
        const pbf::FrameReport r = sim.advanceFrame();
        s.peakKineticEnergy = std::max(s.peakKineticEnergy, r.state.kineticEnergy);
        s.maxEscaped = std::max(s.maxEscaped, r.state.escaped);
    }
    s.end = sim.report().state;
    s.finalHeight = 2.0 * meanHeight(sim.particles());
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
    EXPECT_EQ(s.maxEscaped, 0u);
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
    const pbf::Scene scene = pbf::parseScene(json, "blob.json");
    pbf::ParticleStore p = pbf::createParticles(scene);
    std::mt19937 rng(6);
    std::normal_distribution<float> speed(0.0f, 0.5f);
    // Random velocities and a compressed lattice so the constraint is active.
    for (std::size_t i = 0; i < p.size(); ++i) {
        p.velocity.set(i, {speed(rng), speed(rng), speed(rng)});
        p.position.set(i, p.position.get(i) * 0.85f);
    }
    pbf::Solver solver(scene.simulation);
    const pbf::StateStatistics before =
        pbf::computeStatistics(p, solver.constants(), scene.simulation.domain);
    double scale = 0.0;  // sum of |m v|, the size of the rounding error
    for (std::size_t i = 0; i < p.size(); ++i)
        scale += solver.constants().particleMass * pbf::length(p.velocity.get(i));
    solver.step(p, 1.0f / 240.0f);
    // The compressed blob really activates the density constraint.
    EXPECT_GT(
        pbf::computeStatistics(p, solver.constants(), scene.simulation.domain).maxDensityError,
        0.2);
    for (int k = 1; k < 50; ++k) solver.step(p, 1.0f / 240.0f);
    const pbf::StateStatistics after =
        pbf::computeStatistics(p, solver.constants(), scene.simulation.domain);
    for (int axis = 0; axis < 3; ++axis)
        EXPECT_NEAR(after.momentum[axis], before.momentum[axis], 1e-4 * scale) << "axis " << axis;
}

TEST(Physics, RestLatticeHasRestDensity) {
    // The particle mass is chosen so that an interior particle of the initial
    // lattice has exactly rest density: a resting block starts unstressed.
    const std::string json = R"({
      "domain": {"min": [0, 0, 0], "max": [1, 1, 1]}, "gravity": [0, 0, 0],
      "particle_radius": 0.02,
      "fluid_blocks": [{"min": [0.2, 0.2, 0.2], "max": [0.6, 0.6, 0.6]}]})";
    const pbf::Scene scene = pbf::parseScene(json, "lattice.json");
    pbf::ParticleStore p = pbf::createParticles(scene);
    pbf::Solver solver(scene.simulation);
    solver.step(p, 1e-6f);
    const float centre = 0.4f;
    for (std::size_t i = 0; i < p.size(); ++i) {
        const Vec3 x = p.position.get(i);
        if (std::fabs(x.x - centre) < 0.05f && std::fabs(x.y - centre) < 0.05f &&
            std::fabs(x.z - centre) < 0.05f) {
            EXPECT_NEAR(p.density[i], 1000.0f, 1.0f);
        }
    }
}

TEST(Physics, DamBreakNeverExplodesAndNothingEscapes) {
    // Coarse dam break through the impact on the far wall with adaptive substeps.
    pbf::Scene scene = pbf::loadScene(pbf::test::scenePath("dam_break.json"),
                                      {pbf::parseOverride("particle_radius=0.02")});
    pbf::Simulation sim(scene);
    double maxSpeed = 0.0;
    while (sim.time() < 1.5) {
        const pbf::FrameReport r = sim.advanceFrame();
        ASSERT_EQ(r.state.escaped, 0u) << "frame " << r.frame;
        maxSpeed = std::max(maxSpeed, r.state.maxSpeed);
    }
    // A column of height H = 0.7 m cannot produce speeds far beyond sqrt(2 g H) ~ 3.7 m/s.
    EXPECT_LT(maxSpeed, 2.0 * std::sqrt(2.0 * 9.81 * 0.7));
    EXPECT_LT(sim.report().state.averageDensityError, 0.05);
}

}  // namespace
