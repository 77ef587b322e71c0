// The statistics of a run as one figure (`pbf plot`, the end of `pbf run`).
#include <fmt/format.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "pbf/run/run.hpp"

namespace pbf {
namespace {

namespace fs = std::filesystem;

// The values of the rows where `keep` is not zero.
std::vector<double> where(const std::vector<double>& values, const std::vector<double>& keep) {
    std::vector<double> out;
    for (std::size_t k = 0; k < values.size(); ++k)
        if (keep[k] != 0.0) out.push_back(values[k]);
    return out;
}

std::vector<double> scaled(const std::vector<double>& values, double factor) {
    std::vector<double> out(values);
    for (double& v : out) v *= factor;
    return out;
}

// The scene name summary.json records; the directory's name without one.
std::string sceneNameOf(const fs::path& runDirectory) {
    std::ifstream in(runDirectory / "summary.json");
    if (in) {
        const nlohmann::json summary = nlohmann::json::parse(in, nullptr, false);
        if (summary.is_object() && summary.contains("scene") && summary["scene"].is_string())
            return summary["scene"].get<std::string>();
    }
    return fs::absolute(runDirectory).lexically_normal().filename().string();
}

}  // namespace

plot::Figure statsFigure(const StatsTable& stats, const std::string& sceneName) {
    using plot::Series;
    using plot::Style;
    const std::vector<double>& t = stats.column("time");
    const std::string time = "simulated time (s)";
    const std::vector<double>& particles = stats.column("particles");
    // Frame 0 is the initial state: no step, so no substeps or step time to show.
    const std::vector<double>& substeps = stats.column("substeps");
    const std::vector<double> stepped = where(t, substeps);
    const auto perStep = [&](const char* column) { return where(stats.column(column), substeps); };
    plot::Figure figure;
    figure.title = fmt::format("{}: statistics per frame ({} frames, {:.0f} particles at the end)",
                               sceneName, stats.rows(), particles.back());
    figure.columns = 2;
    figure.panels = {
        {"Density error (compression, max(rho/rho0 - 1, 0))",
         time,
         "density error (%)",
         {Series{"average", t, scaled(stats.column("avg_density_error"), 100.0), Style::Line},
          Series{"maximum", t, scaled(stats.column("max_density_error"), 100.0), Style::Line}}},
        {"Kinetic energy",
         time,
         "kinetic energy (J)",
         {Series{"1/2 m sum |v|^2", t, stats.column("kinetic_energy"), Style::Line}}},
        {"Particles", time, "particles", {Series{"count", t, particles, Style::Line}}},
        {"Substeps per frame (CFL-limited or fixed)",
         time,
         "substeps",
         {Series{"substeps", stepped, perStep("substeps"), Style::Line}}},
        {"Wall-clock time per substep",
         time,
         "step time (ms)",
         {Series{"whole step", stepped, perStep("step_ms"), Style::Line},
          Series{"neighbour search", stepped, perStep("neighbor_ms"), Style::Dashed},
          Series{"density solve", stepped, perStep("solve_ms"), Style::Dashed},
          Series{"predict + post-process", stepped, perStep("post_ms"), Style::Dashed}}},
        {"Fastest particle",
         time,
         "max speed (m/s)",
         {Series{"max |v|", t, stats.column("max_speed"), Style::Line}}},
    };
    return figure;
}

plot::Result plotRunStatistics(const fs::path& runDirectory, const fs::path& png) {
    std::error_code ec;
    if (!fs::is_directory(runDirectory, ec))
        throw IoError(runDirectory.string() + ": no such directory");
    const StatsTable stats = readStatsCsv(runDirectory / "stats.csv");
    return plot::drawFigures({{statsFigure(stats, sceneNameOf(runDirectory)), png}});
}

}  // namespace pbf
