// Subcommands of the `pbf` program. Each registers its options on the CLI11
// app and returns the exit code from its run function.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>

namespace pbf::cli {

// Registers the subcommand and returns the function that runs it after parsing.
std::function<int()> addRunCommand(CLI::App& app);
std::function<int()> addBenchCommand(CLI::App& app);
std::function<int()> addFoamCommand(CLI::App& app);
std::function<int()> addExportCommand(CLI::App& app);
#ifdef PBF_HAVE_RENDER
std::function<int()> addViewCommand(CLI::App& app);
std::function<int()> addRenderCommand(CLI::App& app);
#endif
std::function<int()> addMeshCommand(CLI::App& app);
std::function<int()> addPlotCommand(CLI::App& app);
std::function<int()> addValidateCommand(CLI::App& app);
std::function<int()> addParamsCommand(CLI::App& app);

}  // namespace pbf::cli
