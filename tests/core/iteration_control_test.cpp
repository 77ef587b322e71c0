// Accuracy per cost (docs/performance.md, "Accuracy per cost"): iterating
// to a tolerance (solver.max_density_error), over-relaxation and the warm
// start, each checked for what it promises on a coarse dam break.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "pbf/io/scene.hpp"
#include "pbf/world/world.hpp"
#include "support/test_util.hpp"

namespace pbf::test {
namespace {

// The dam break at 8.7k particles (particle_radius 0.0125) through the
// impact on the far wall, with adaptive substeps as users run it.
Scene damBreak(const std::vector<std::string>& settings) {
    std::vector<SceneOverride> overrides{parseOverride("particle_radius=0.0125")};
    for (const std::string& s : settings) overrides.push_back(parseOverride(s));
    return loadScene(scenePath("dam_break.json"), overrides);
}

struct Solve {
    std::vector<FrameReport> frames;
    double meanAverageError = 0.0;  // time average of the per-frame average compression
    double meanMaxError = 0.0;
    double meanIterations = 0.0;
    double peakSpeed = 0.0;
    int substeps = 0;
};

Solve solve(const std::vector<std::string>& settings, int frames) {
    World world(damBreak(settings));
    Solve r;
    for (int k = 0; k < frames; ++k) {
        r.frames.push_back(stepFrame(world));
        const FrameReport& f = r.frames.back();
        r.meanAverageError += f.state.averageDensityError / frames;
        r.meanMaxError += f.state.maxDensityError / frames;
        r.meanIterations += f.iterations / frames;
        r.substeps += f.substeps;
        r.peakSpeed = std::max(r.peakSpeed, f.state.maxSpeed);
    }
    return r;
}

void print(const char* label, const Solve& r) {
    std::printf(
        "  %-28s avg %.4f %%  max %.3f %%  iterations %.2f  substeps %d  peak speed "
        "%.2f m/s\n",
        label, 100.0 * r.meanAverageError, 100.0 * r.meanMaxError, r.meanIterations, r.substeps,
        r.peakSpeed);
}

constexpr int kFrames = 24;  // 0.8 s: the surge hits the far wall at ~0.5 s

// The tolerance is met where it is measured: the state a frame ends with is
// the one whose density pass stopped the iterations, so its average
// compression is at most the tolerance, every frame. The work follows the
// flow: few iterations while the column stands, many at the impact. Checked
// that this can fail: with the convergence test ignored (fixed 4
// iterations) frames exceed 0.05 % (the fixed run below shows it).
TEST(IterationControl, ToleranceIsMetEveryFrameAndIterationsFollowTheFlow) {
    const double tolerance = 0.0005;
    const Solve fixed = solve({"solver.iterations=4"}, kFrames);
    const Solve controlled = solve(
        {"solver.max_density_error=0.0005", "solver.min_iterations=1", "solver.max_iterations=200"},
        kFrames);
    print("4 iterations", fixed);
    print("tolerance 0.05 %", controlled);
    double fewest = 1e9, most = 0.0;
    for (const FrameReport& f : controlled.frames) {
        EXPECT_LE(f.state.averageDensityError, tolerance) << "frame " << f.frame;
        EXPECT_LT(f.iterations, 200.0) << "frame " << f.frame << " hit the iteration cap";
        fewest = std::min(fewest, f.iterations);
        most = std::max(most, f.iterations);
    }
    const auto worstFixed = std::max_element(
        fixed.frames.begin(), fixed.frames.end(),
        [](auto& a, auto& b) { return a.state.averageDensityError < b.state.averageDensityError; });
    EXPECT_GT(worstFixed->state.averageDensityError, tolerance)
        << "the fixed run never needed the tolerance: the test checks nothing";
    std::printf("  iterations per substep: %.2f to %.2f\n", fewest, most);
    EXPECT_GE(most, 2.0 * fewest) << "the iteration count does not follow the flow";
}

// A tighter tolerance costs more iterations and gives a smaller error: the
// control is monotone, so a user can trade one for the other.
TEST(IterationControl, TighterToleranceGivesSmallerErrorForMoreIterations) {
    const auto withTolerance = [](const char* tolerance) {
        return solve({std::string("solver.max_density_error=") + tolerance,
                      "solver.min_iterations=1", "solver.max_iterations=200"},
                     kFrames);
    };
    const Solve loose = withTolerance("0.001");
    const Solve tight = withTolerance("0.0002");
    print("tolerance 0.1 %", loose);
    print("tolerance 0.02 %", tight);
    EXPECT_LT(tight.meanAverageError, 0.5 * loose.meanAverageError);
    EXPECT_LT(tight.meanMaxError, loose.meanMaxError);
    EXPECT_GT(tight.meanIterations, loose.meanIterations);
}

// Over-relaxation (omega 1.2) and the warm start (0.8) each lower the error
// of the same number of iterations; together they beat twice the
// iterations of the plain solver on the average compression. Measured on
// this scene (time averages of the average compression): 4 it 0.149 %,
// omega 0.118 %, warm 0.061 %, both 0.050 %, 8 plain iterations 0.063 %.
TEST(IterationControl, OverRelaxationAndWarmStartConvergeFaster) {
    const Solve plain = solve({"solver.iterations=4"}, kFrames);
    const Solve omega = solve({"solver.iterations=4", "solver.over_relaxation=1.2"}, kFrames);
    const Solve warm = solve({"solver.iterations=4", "solver.warm_start=0.8"}, kFrames);
    const Solve both = solve(
        {"solver.iterations=4", "solver.over_relaxation=1.2", "solver.warm_start=0.8"}, kFrames);
    const Solve twice = solve({"solver.iterations=8"}, kFrames);
    print("4 iterations", plain);
    print("4, omega 1.2", omega);
    print("4, warm start 0.8", warm);
    print("4, omega 1.2, warm 0.8", both);
    print("8 iterations", twice);
    EXPECT_LT(omega.meanAverageError, plain.meanAverageError);
    EXPECT_LT(warm.meanAverageError, plain.meanAverageError);
    EXPECT_LT(both.meanAverageError, std::min(omega.meanAverageError, warm.meanAverageError));
    EXPECT_LT(both.meanAverageError, twice.meanAverageError);
    // Stable: the maximum compression no worse, and no energy from nowhere:
    // the splash's peak speed stays that of the plain solver's flow (the
    // warm start of every particle, compressed or not, was measured to add
    // energy: 17 % more substeps and peak speeds 8 m/s at w = 0.4).
    EXPECT_LE(both.meanMaxError, plain.meanMaxError);
    for (const Solve* r : {&omega, &warm, &both})
        EXPECT_LT(r->peakSpeed, 1.3 * std::max(plain.peakSpeed, twice.peakSpeed));
}

}  // namespace
}  // namespace pbf::test
