// `pbf`: the command-line program. Subcommands live in *_command.cpp.
#include <CLI/CLI.hpp>
#include <exception>

#include "commands.hpp"
#include "console.hpp"
#include "pbf/version.hpp"

int main(int argc, char** argv) {
    CLI::App app{"pbf: Position Based Fluids water simulator (Macklin & Mueller 2013)", "pbf"};
    app.set_version_flag("--version", std::string("pbf ") + pbf::kVersion);
    app.require_subcommand(1);
    const auto run = pbf::cli::addRunCommand(app);
    const auto bench = pbf::cli::addBenchCommand(app);
#ifdef PBF_HAVE_RENDER
    const auto view = pbf::cli::addViewCommand(app);
    const auto render = pbf::cli::addRenderCommand(app);
#endif
    const auto mesh = pbf::cli::addMeshCommand(app);
    const auto foam = pbf::cli::addFoamCommand(app);
    const auto plot = pbf::cli::addPlotCommand(app);
    const auto validate = pbf::cli::addValidateCommand(app);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e);
    }
    try {
        if (app.got_subcommand("run")) return run();
        if (app.got_subcommand("bench")) return bench();
#ifdef PBF_HAVE_RENDER
        if (app.got_subcommand("view")) return view();
        if (app.got_subcommand("render")) return render();
#endif
        if (app.got_subcommand("mesh")) return mesh();
        if (app.got_subcommand("foam")) return foam();
        if (app.got_subcommand("plot")) return plot();
        if (app.got_subcommand("validate")) return validate();
    } catch (const std::exception& e) {
        pbf::cli::printError(e.what());
        return 1;
    }
    return 2;
}
