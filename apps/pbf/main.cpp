// `pbf`: the command-line program. Subcommands live in *_command.cpp.
#include <CLI/CLI.hpp>
#include <exception>
#include <functional>
#include <string>

#include "commands.hpp"
#include "console.hpp"
#include "device_option.hpp"
#include "pbf/core/distributed.hpp"

namespace {

// Runs a subcommand. Distributed (mpirun -np N, N > 1): a failure on one
// rank is reported naming the rank and ends the whole job (MPI_Abort), as
// the other ranks would otherwise wait for it in their next exchange.
int runCommand(const std::function<int()>& command) {
    const bool distributed = pbf::distributed::size() > 1;
    int status = 1;
    try {
        status = command();
    } catch (const std::exception& e) {
        pbf::cli::printError(distributed
                                 ? "rank " + std::to_string(pbf::distributed::rank()) + " of " +
                                       std::to_string(pbf::distributed::size()) + ": " + e.what()
                                 : std::string(e.what()));
        if (distributed) pbf::distributed::abort(1);
        return 1;
    }
    pbf::distributed::finalize();
    return status;
}

}  // namespace

int main(int argc, char** argv) {
    try {
        pbf::distributed::initialize(argc, argv);
    } catch (const std::exception& e) {
        pbf::cli::printError(e.what());
        return 1;
    }
    CLI::App app{"pbf: Position Based Fluids water simulator (Macklin & Mueller 2013)", "pbf"};
    app.set_version_flag(
        "--version", [] { return pbf::cli::versionText(); },
        "Print the version and the devices built in, then exit");
    app.require_subcommand(1);
    const auto run = pbf::cli::addRunCommand(app);
    const auto bench = pbf::cli::addBenchCommand(app);
#ifdef PBF_HAVE_RENDER
    const auto view = pbf::cli::addViewCommand(app);
    const auto render = pbf::cli::addRenderCommand(app);
#endif
    const auto mesh = pbf::cli::addMeshCommand(app);
    const auto foam = pbf::cli::addFoamCommand(app);
    const auto exporter = pbf::cli::addExportCommand(app);
    const auto plot = pbf::cli::addPlotCommand(app);
    const auto validate = pbf::cli::addValidateCommand(app);
    const auto params = pbf::cli::addParamsCommand(app);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        const int status = app.exit(e);
        pbf::distributed::finalize();
        return status;
    }
    if (app.got_subcommand("run")) return runCommand(run);
    if (app.got_subcommand("bench")) return runCommand(bench);
    if (pbf::distributed::size() > 1) {
        pbf::cli::printError("only pbf run and pbf bench run distributed (mpirun -np N)");
        pbf::distributed::abort(2);
    }
#ifdef PBF_HAVE_RENDER
    if (app.got_subcommand("view")) return runCommand(view);
    if (app.got_subcommand("render")) return runCommand(render);
#endif
    if (app.got_subcommand("mesh")) return runCommand(mesh);
    if (app.got_subcommand("foam")) return runCommand(foam);
    if (app.got_subcommand("export")) return runCommand(exporter);
    if (app.got_subcommand("plot")) return runCommand(plot);
    if (app.got_subcommand("validate")) return runCommand(validate);
    if (app.got_subcommand("params")) return runCommand(params);
    return 2;
}
