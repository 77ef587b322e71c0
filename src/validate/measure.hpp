// Helpers shared by the validation cases (private header): stepping a world,
// interpolating measured series at reference times, fitting.
#pragma once

#include <string>
#include <vector>

#include "pbf/validate.hpp"
#include "pbf/world.hpp"

namespace pbf::validation::detail {

// Steps one frame; a frame that fails throws std::runtime_error with the
// world's message (the case then fails with it).
FrameReport step(World& world);

// (xs, ys) at x by linear interpolation; xs increasing. NaN outside [xs.front(), xs.back()].
double interpolate(const std::vector<double>& xs, const std::vector<double>& ys, double x);

// Root mean square of the values.
double rms(const std::vector<double>& values);

// Least-squares line y = intercept + slope x.
struct Line {
    double intercept = 0.0;
    double slope = 0.0;
};
Line fitLine(const std::vector<double>& x, const std::vector<double>& y);

// Adds `x`, `y` as a column of the case's CSV and returns them as a plot series.
plot::Series record(CaseResult& result, const std::string& series, const std::string& xName,
                    const std::vector<double>& x, const std::string& yName,
                    const std::vector<double>& y, plot::Style style = plot::Style::Line);

}  // namespace pbf::validation::detail
