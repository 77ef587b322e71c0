// Plots: the one plotting path of pbf (`pbf plot`, the end of `pbf run`,
// `pbf validate`).
//
// A Figure is plain data: panels of labelled series. drawFigures() writes
// each figure's data beside its PNG (`<name>.plot.json`, the numbers the
// PNG shows) and runs scripts/pbf_plot.py with Debian's Python
// (/usr/bin/python3, matplotlib from python3-matplotlib) to draw them, all
// figures in one Python process. Where Python or matplotlib is missing the
// data files are still written and the result says what to install; nothing
// throws for a missing plotting dependency.
//
// The script is looked up (pbf::plotScript) as $PBF_PLOT_SCRIPT, then
// pbf_plot.py beside the running executable (the build copies it there),
// then scripts/pbf_plot.py in the source tree the binary was built from. The
// interpreter is $PBF_PYTHON, else /usr/bin/python3 (run with -E, so that a
// PYTHONPATH or PYTHONHOME meant for another Python does not leak in).
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "pbf/io/io.hpp"

namespace pbf::plot {

enum class Style {
    Line,    // a solid line
    Dashed,  // a dashed line (references, tolerances)
    Points,  // markers only (measurements, experiments)
};

struct Series {
    std::string label;
    std::vector<double> x;
    std::vector<double> y;
    Style style = Style::Line;
};

struct Panel {
    std::string title;
    std::string xLabel;  // with the unit, e.g. "simulated time (s)"
    std::string yLabel;
    std::vector<Series> series;
    bool logY = false;
};

struct Figure {
    std::string title;
    std::vector<Panel> panels;
    int columns = 2;  // panels per row
};

// The JSON the script reads (also written beside the PNG); throws
// std::invalid_argument for a series whose x and y differ in length.
std::string toJson(const Figure& figure);

// `<png without .png>.plot.json`: where drawFigures writes the data of `png`.
std::filesystem::path dataFileFor(const std::filesystem::path& png);

struct Job {
    Figure figure;
    std::filesystem::path png;
};

struct Result {
    bool drawn = false;              // every PNG was written
    bool missingDependency = false;  // Python or matplotlib is not installed
    std::string message;             // why not (what to install, or the script's error)
};

// The message drawFigures gives when matplotlib (or Python) is missing.
std::string missingDependencyMessage();

// Writes every job's data file (IoError naming the file if that fails) and
// draws all PNGs with one Python process.
Result drawFigures(const std::vector<Job>& jobs);

// Where the plotting script is (see above), if it exists.
std::optional<std::filesystem::path> plotScript();

}  // namespace pbf::plot
