#include "pbf/run/plot.hpp"

#include <cstdlib>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <system_error>

#include "pbf/io/process.hpp"

namespace pbf::plot {
namespace {

namespace fs = std::filesystem;

// Set by src/CMakeLists.txt for this file only.
#ifndef PBF_PLOT_SCRIPT_SOURCE
#define PBF_PLOT_SCRIPT_SOURCE ""
#endif

constexpr const char* kScriptName = "pbf_plot.py";
// The script exits with this status when `import matplotlib` fails.
constexpr int kExitMissingMatplotlib = 3;

const char* styleName(Style style) {
    switch (style) {
        case Style::Dashed:
            return "dashed";
        case Style::Points:
            return "points";
        case Style::Line:
            break;
    }
    return "line";
}

bool isFile(const fs::path& path) {
    std::error_code ec;
    return !path.empty() && fs::is_regular_file(path, ec);
}

fs::path pythonInterpreter() {
    const char* chosen = std::getenv("PBF_PYTHON");
    return chosen != nullptr && *chosen != '\0' ? fs::path(chosen) : fs::path("/usr/bin/python3");
}

}  // namespace

std::string toJson(const Figure& figure) {
    nlohmann::json panels = nlohmann::json::array();
    for (const Panel& panel : figure.panels) {
        nlohmann::json series = nlohmann::json::array();
        for (const Series& s : panel.series) {
            if (s.x.size() != s.y.size())
                throw std::invalid_argument("plot series '" + s.label +
                                            "': " + std::to_string(s.x.size()) + " x values but " +
                                            std::to_string(s.y.size()) + " y values");
            // NaN and infinity become null (JSON has no NaN); the script leaves a gap.
            series.push_back(
                {{"label", s.label}, {"x", s.x}, {"y", s.y}, {"style", styleName(s.style)}});
        }
        panels.push_back({{"title", panel.title},
                          {"x_label", panel.xLabel},
                          {"y_label", panel.yLabel},
                          {"log_y", panel.logY},
                          {"series", std::move(series)}});
    }
    const nlohmann::json j = {
        {"title", figure.title}, {"columns", figure.columns}, {"panels", std::move(panels)}};
    return j.dump(1, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
}

fs::path dataFileFor(const fs::path& png) {
    fs::path data = png;
    data.replace_extension(".plot.json");
    return data;
}

std::string missingDependencyMessage() {
    return "plots need Python 3 with matplotlib: apt-get install python3-matplotlib "
           "(scripts/install_deps.sh installs it); the plotted data is written beside each PNG "
           "(*.plot.json)";
}

std::optional<fs::path> plotScript() {
    if (const char* chosen = std::getenv("PBF_PLOT_SCRIPT"); chosen != nullptr && *chosen != '\0')
        return isFile(chosen) ? std::optional<fs::path>(chosen) : std::nullopt;
    std::error_code ec;
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    if (!ec && isFile(exe.parent_path() / kScriptName)) return exe.parent_path() / kScriptName;
    if (isFile(PBF_PLOT_SCRIPT_SOURCE)) return fs::path(PBF_PLOT_SCRIPT_SOURCE);
    return std::nullopt;
}

Result drawFigures(const std::vector<Job>& jobs) {
    Result result;
    if (jobs.empty()) {
        result.drawn = true;
        return result;
    }
    std::vector<std::string> argv;
    for (const Job& job : jobs) {
        const std::string json = toJson(job.figure);
        writeFileAtomically(dataFileFor(job.png), [&](std::ostream& out) { out << json; });
        argv.push_back(dataFileFor(job.png).string());
        argv.push_back(job.png.string());
    }
    const fs::path python = pythonInterpreter();
    if (!findProgram(python.string())) {
        result.missingDependency = true;
        result.message = python.string() + " not found; " + missingDependencyMessage();
        return result;
    }
    const std::optional<fs::path> script = plotScript();
    if (!script) {
        result.message = std::string(kScriptName) +
                         " not found (looked at $PBF_PLOT_SCRIPT, beside the pbf executable and "
                         "at " PBF_PLOT_SCRIPT_SOURCE ")";
        return result;
    }
    argv.insert(argv.begin(), {python.string(), "-E", script->string()});
    const ProgramResult run = runProgram(argv);
    if (run.ok()) {
        result.drawn = true;
    } else if (run.started && run.exitStatus == kExitMissingMatplotlib) {
        result.missingDependency = true;
        result.message = missingDependencyMessage();
    } else {
        result.message = script->string() + " failed" +
                         (run.started ? " (exit status " + std::to_string(run.exitStatus) + ")"
                                      : std::string()) +
                         ": " + run.output;
        while (!result.message.empty() && result.message.back() == '\n') result.message.pop_back();
    }
    return result;
}

}  // namespace pbf::plot
