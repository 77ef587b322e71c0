#include "validate/measure.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace pbf::validation::detail {

FrameReport step(World& world) {
    FrameResult result = world.stepFrame();
    if (!result.ok()) throw std::runtime_error(result.error->message);
    return result.report;
}

double interpolate(const std::vector<double>& xs, const std::vector<double>& ys, double x) {
    if (xs.empty() || x < xs.front() || x > xs.back())
        return std::numeric_limits<double>::quiet_NaN();
    for (std::size_t k = 1; k < xs.size(); ++k)
        if (x <= xs[k]) {
            const double span = xs[k] - xs[k - 1];
            const double w = span > 0.0 ? (x - xs[k - 1]) / span : 1.0;
            return ys[k - 1] + w * (ys[k] - ys[k - 1]);
        }
    return ys.back();
}

double rms(const std::vector<double>& values) {
    if (values.empty()) return std::numeric_limits<double>::quiet_NaN();
    double sum = 0.0;
    for (double v : values) sum += v * v;
    return std::sqrt(sum / double(values.size()));
}

Line fitLine(const std::vector<double>& x, const std::vector<double>& y) {
    const double n = double(x.size());
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    for (std::size_t k = 0; k < x.size(); ++k) {
        sx += x[k];
        sy += y[k];
        sxx += x[k] * x[k];
        sxy += x[k] * y[k];
    }
    Line line;
    const double d = n * sxx - sx * sx;
    if (x.size() < 2 || d == 0.0)
        return {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN()};
    line.slope = (n * sxy - sx * sy) / d;
    line.intercept = (sy - line.slope * sx) / n;
    return line;
}

plot::Series record(CaseResult& result, const std::string& series, const std::string& xName,
                    const std::vector<double>& x, const std::string& yName,
                    const std::vector<double>& y, plot::Style style) {
    result.data.push_back({series, xName, yName, x, y});
    return {series, x, y, style};
}

}  // namespace pbf::validation::detail
