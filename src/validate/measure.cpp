#include "validate/measure.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <stdexcept>
#include <utility>

#include "pbf/geometry/solids.hpp"

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

SampleMean sampleMean(const std::vector<double>& values) {
    SampleMean m;
    m.count = values.size();
    if (values.empty()) return m;
    m.mean = std::accumulate(values.begin(), values.end(), 0.0) / double(values.size());
    if (values.size() < 2) return m;
    double squares = 0.0;
    for (const double v : values) squares += (v - m.mean) * (v - m.mean);
    m.standardDeviation = std::sqrt(squares / double(values.size() - 1));
    return m;
}

double SampleMean::standardError() const {
    return count > 0 ? standardDeviation / std::sqrt(double(count)) : 0.0;
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

std::string runLabel(float radius, float consistentCorrection) {
    if (consistentCorrection > 0.0f)
        return fmt::format("r = {:g} mm, consistent_correction {:g}", 1e3 * radius,
                           consistentCorrection);
    return fmt::format("r = {:g} mm", 1e3 * radius);
}

plot::Series record(CaseResult& result, const std::string& series, const std::string& xName,
                    const std::vector<double>& x, const std::string& yName,
                    const std::vector<double>& y, plot::Style style) {
    result.data.push_back({series, xName, yName, x, y});
    return {series, x, y, style};
}

double restingTimeStep(float radius) {
    const double spacing = 2.0 * radius;
    return std::min(1.0 / 240.0, std::sqrt(0.0086 * spacing / 9.81));
}

double waterLevel(const World& world, double clearance) {
    const ParticleStore& p = world.particles();
    const float cell = world.definition().simulation.particleSpacing();
    std::map<std::pair<int, int>, float> highest;
    for (std::size_t i = 0; i < p.size(); ++i) {
        const Vec3 x = p.position.get(i);
        const auto key = std::make_pair(int(std::floor(x.x / cell)), int(std::floor(x.z / cell)));
        const auto [it, inserted] = highest.emplace(key, x.y);
        if (!inserted) it->second = std::max(it->second, x.y);
    }
    // Columns are chosen by their centres, whole: choosing particles by
    // their own distance split the columns the clearance circle crosses, and
    // such a column's highest particle outside the circle can lie anywhere
    // down to the floor. Those few columns read the level 3-4 mm low at r =
    // 5 mm (the floating-depth bias; docs/validation.md, Archimedes).
    double sum = 0.0;
    std::size_t columns = 0;
    for (const auto& [key, y] : highest) {
        const float cx = (float(key.first) + 0.5f) * cell, cz = (float(key.second) + 0.5f) * cell;
        bool nearBody = false;
        for (const RigidBodyState& b : world.bodyStates())
            nearBody = nearBody || std::hypot(cx - b.position.x, cz - b.position.z) < clearance;
        if (nearBody) continue;
        sum += y;
        ++columns;
    }
    if (columns == 0) return std::numeric_limits<double>::quiet_NaN();
    return sum / double(columns) + world.definition().simulation.particleRadius;
}

double submergedFraction(const World& world, std::size_t body, double level, int samples) {
    const RigidBodyInfo& info = world.bodyInfos().at(body);
    const RigidBodyState& s = world.bodyStates()[body];
    const Pose pose{s.position, s.orientation};
    const Solid& shape = world.solids().shape(info.solid);
    const Aabb box = shape.bounds();  // in the shape's own frame
    const Vec3 extent = box.extent();
    long inside = 0, below = 0;
    for (int a = 0; a < samples; ++a)
        for (int b = 0; b < samples; ++b)
            for (int c = 0; c < samples; ++c) {
                const auto at = [&](int k) { return (float(k) + 0.5f) / float(samples); };
                const Vec3 local{box.min.x + at(a) * extent.x, box.min.y + at(b) * extent.y,
                                 box.min.z + at(c) * extent.z};
                Vec3 normal;
                if (shape.signedDistance(local, normal) >= 0.0f) continue;
                ++inside;
                if (pose.toWorld(info.shapeInBody.toWorld(local)).y < level) ++below;
            }
    return inside > 0 ? double(below) / double(inside) : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace pbf::validation::detail
