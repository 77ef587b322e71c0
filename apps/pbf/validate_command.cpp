// `pbf validate [CASE ...] [--quick] [--out DIR]`: the physics checked
// against experiments and closed forms (include/pbf/validate/validate.hpp,
// docs/validation.md).
#include <fmt/format.h>

#include <chrono>
#include <exception>
#include <memory>
#include <string>
#include <vector>

#include "commands.hpp"
#include "console.hpp"
#include "pbf/core/threading.hpp"
#include "pbf/validate/validate.hpp"

namespace pbf::cli {
namespace {

struct ValidateArguments {
    std::vector<std::string> cases;
    bool quick = false;
    std::string out;
    int threads = 0;
    bool quiet = false;
    bool list = false;
};

// A case that throws (a world that failed, an unexpected error) is reported
// as a failed case with the message, and the others still run.
validation::CaseResult runCase(const validation::Case& c, const validation::Options& options) {
    const auto start = std::chrono::steady_clock::now();
    validation::CaseResult result;
    try {
        result = c.run(options);
    } catch (const std::exception& e) {
        result.name = c.name;
        result.title = c.description;
        result.notes = std::string("The case stopped with an error: ") + e.what();
        result.checks.push_back({"case ran to the end", 0.0, 1.0, 0.0, "", "", e.what()});
    }
    result.wallSeconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return result;
}

int runValidate(const ValidateArguments& args) {
    const std::vector<validation::Case>& all = validation::cases();
    if (args.list) {
        for (const validation::Case& c : all) fmt::print("{:<16} {}\n", c.name, c.description);
        return 0;
    }
    std::vector<const validation::Case*> chosen;
    for (const std::string& name : args.cases) {
        const validation::Case* found = nullptr;
        for (const validation::Case& c : all)
            if (c.name == name) found = &c;
        if (!found) {
            std::string known;
            for (const validation::Case& c : all) known += (known.empty() ? "" : ", ") + c.name;
            throw CLI::ValidationError("CASE",
                                       "unknown case '" + name + "' (cases: " + known + ")");
        }
        chosen.push_back(found);
    }
    if (chosen.empty())
        for (const validation::Case& c : all) chosen.push_back(&c);
    if (args.threads > 0) setThreadCount(args.threads);
    const std::string out =
        !args.out.empty() ? args.out : (args.quick ? "out/validate_quick" : "out/validate");

    validation::Options options;
    options.quick = args.quick;
    if (!args.quiet)
        options.progress = [](const std::string& message) {
            fmt::print(stderr, "pbf validate: {}\n", message);
        };
    std::vector<validation::CaseResult> results;
    for (const validation::Case* c : chosen) {
        if (options.progress) options.progress(c->name + ": " + c->description);
        results.push_back(runCase(*c, options));
        if (options.progress)
            options.progress(fmt::format("{}: {} in {:.1f} s", c->name,
                                         results.back().passed() ? "passed" : "FAILED",
                                         results.back().wallSeconds));
    }
    const plot::Result plots = validation::writeReport(out, results, options);
    if (!plots.drawn) fmt::print(stderr, "pbf: warning: no plots: {}\n", plots.message);
    fmt::print("{}", validation::formatTable(results));
    int failed = 0;
    for (const validation::CaseResult& r : results) failed += r.passed() ? 0 : 1;
    fmt::print("pbf validate: {} of {} cases passed{} -> {}/summary.md\n",
               int(results.size()) - failed, results.size(), args.quick ? " (--quick)" : "", out);
    return failed == 0 ? 0 : 6;
}

}  // namespace

std::function<int()> addValidateCommand(CLI::App& app) {
    auto args = std::make_shared<ValidateArguments>();
    CLI::App* cmd = app.add_subcommand(
        "validate",
        "Check the physics against experiments and closed forms (docs/validation.md): prints a "
        "table, writes a report (CSV + PNG per case, summary.md), exits 6 if a case fails");
    cmd->add_option("cases", args->cases, "Cases to run (default: all; --list shows them)");
    cmd->add_flag("--quick", args->quick,
                  "Reduced resolutions (a few minutes on two cores; what the test suite runs)");
    cmd->add_option("-o,--out", args->out,
                    "Report directory (default: out/validate, or out/validate_quick with --quick)");
    cmd->add_option("-t,--threads", args->threads, "Worker threads (default: all cores)")
        ->check(CLI::Range(1, 1024));
    cmd->add_flag("-q,--quiet", args->quiet, "No progress messages");
    cmd->add_flag("--list", args->list, "List the cases and exit");
    return [args] { return runValidate(*args); };
}

}  // namespace pbf::cli
