// Helpers shared by the validation cases (private header): stepping a world,
// interpolating measured series at reference times, fitting, and how deep a
// floating body lies (also used by tests/bodies/bodies_test.cpp).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "pbf/validate/validate.hpp"
#include "pbf/world/world.hpp"

namespace pbf::validation::detail {

// Steps one frame; a frame that fails throws std::runtime_error with the
// world's message (the case then fails with it).
FrameReport step(World& world);

// (xs, ys) at x by linear interpolation; xs increasing. NaN outside [xs.front(), xs.back()].
double interpolate(const std::vector<double>& xs, const std::vector<double>& ys, double x);

// Root mean square of the values.
double rms(const std::vector<double>& values);

// The mean of samples, their standard deviation (with n - 1; 0 for one
// sample) and the mean's standard error.
struct SampleMean {
    double mean = 0.0;
    double standardDeviation = 0.0;
    std::size_t count = 0;
    double standardError() const;
};
SampleMean sampleMean(const std::vector<double>& values);

// Least-squares line y = intercept + slope x.
struct Line {
    double intercept = 0.0;
    double slope = 0.0;
};
Line fitLine(const std::vector<double>& x, const std::vector<double>& y);

// A run's name in plots and CSV: "r = 5 mm", or "r = 5 mm,
// consistent_correction 0.45" for a run with solver.consistent_correction.
std::string runLabel(float radius, float consistentCorrection = 0.0f);

// Adds `x`, `y` as a column of the case's CSV and returns them as a plot series.
plot::Series record(CaseResult& result, const std::string& series, const std::string& xName,
                    const std::vector<double>& x, const std::string& yName,
                    const std::vector<double>& y, plot::Style style = plot::Style::Line);

// The largest substep (s) that lets a tank of particles of this radius come
// to rest: PBF's residual velocity noise comes from each step's gravity push
// g dt^2 that 4 Jacobi iterations do not remove entirely
// (include/pbf/core/params.hpp); it must stay a small share of the spacing. The
// default cap of 1/240 s keeps g dt^2 below 0.9 % of a 2 cm spacing; finer
// spacings get the same share (measured: 5 mm spacing at 1/240 s boils at
// 0.06 m/s median speed).
double restingTimeStep(float radius);

// Floating bodies. The submerged fraction is measured, not computed from
// the forces: the water level from the particles, and the share of the
// body's volume below it.
//
// The water level: the mean over the 2r x 2r columns (r the particle
// radius) whose centres are farther than `clearance` (m, horizontally) from
// every body's centre of the highest particle in each, plus r (the
// lattice's top layer sits r below the surface). NaN if no column is clear
// of the bodies.
double waterLevel(const World& world, double clearance);

// The share of rigid body i's volume below the height `level` (m): the
// points of a samples^3 grid over its shape's bounds that lie inside the
// shape (signed distance < 0), posed where the body is, counted below the level.
double submergedFraction(const World& world, std::size_t body, double level, int samples = 24);

}  // namespace pbf::validation::detail
