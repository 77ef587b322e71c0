// `pbf plot RUN_DIR`: the statistics of a run (stats.csv) as one PNG.
#include <fmt/format.h>

#include <filesystem>
#include <memory>
#include <string>

#include "commands.hpp"
#include "console.hpp"
#include "pbf/run/run.hpp"

namespace pbf::cli {
namespace {

struct PlotArguments {
    std::string directory;
    std::string out;
};

int runPlot(const PlotArguments& args) {
    const std::filesystem::path png = args.out.empty()
                                          ? std::filesystem::path(args.directory) / "stats.png"
                                          : std::filesystem::path(args.out);
    const plot::Result result = plotRunStatistics(args.directory, png);
    if (!result.drawn) {
        // The plot is all this command makes: without it the command failed.
        printError(result.message);
        return result.missingDependency ? 5 : 1;
    }
    fmt::print("pbf plot: {} -> {}\n", args.directory, png.string());
    return 0;
}

}  // namespace

std::function<int()> addPlotCommand(CLI::App& app) {
    auto args = std::make_shared<PlotArguments>();
    CLI::App* cmd = app.add_subcommand(
        "plot",
        "Plot a run's statistics (stats.csv): density error, kinetic energy, particles, "
        "substeps and step time against simulated time, as one PNG (matplotlib)");
    cmd->add_option("run_dir", args->directory, "Output directory of `pbf run`")->required();
    cmd->add_option("-o,--out", args->out, "PNG to write (default: RUN_DIR/stats.png)");
    return [args] { return runPlot(*args); };
}

}  // namespace pbf::cli
