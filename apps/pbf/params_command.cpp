// `pbf params`: every simulation parameter (the parameter table,
// include/pbf/core/param_table.hpp) with its unit, default, valid range and
// whether it can change while a world runs; `--markdown` prints the table of
// docs/scenes.md.
#include <fmt/format.h>

#include <memory>
#include <string>

#include "commands.hpp"
#include "pbf/core/param_table.hpp"

namespace pbf::cli {
namespace {

int runParams(bool markdown) {
    if (markdown) {
        fmt::print("{}", paramTableMarkdown());
        return 0;
    }
    std::size_t width = 0;
    for (const ParamInfo& p : paramTable()) width = std::max(width, p.path.size());
    for (const ParamInfo& p : paramTable()) {
        const std::string value = p.required ? "required" : defaultText(p);
        fmt::print("{:<{}}  {:<8} default {:<14} range {}{}\n", p.path, width,
                   p.unit.empty() ? "-" : std::string(p.unit), value, rangeText(p),
                   p.live ? "" : "  (fixed while a world runs)");
        fmt::print("{:<{}}  {}\n", "", width, p.description);
    }
    return 0;
}

}  // namespace

std::function<int()> addParamsCommand(CLI::App& app) {
    auto markdown = std::make_shared<bool>(false);
    CLI::App* cmd = app.add_subcommand(
        "params",
        "List every simulation parameter: scene path (also --set FIELD=VALUE and Python's "
        "world.settings), unit, default, valid range, description");
    cmd->add_flag("--markdown", *markdown, "Print the Markdown table of docs/scenes.md");
    return [markdown] { return runParams(*markdown); };
}

}  // namespace pbf::cli
