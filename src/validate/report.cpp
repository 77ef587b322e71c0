// The table, the CSV files and the Markdown summary of `pbf validate`.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <sstream>

#include "pbf/core/version.hpp"
#include "pbf/io/io.hpp"
#include "pbf/validate/validate.hpp"

namespace pbf::validation {
namespace {

namespace fs = std::filesystem;

// Numbers as people read them: 4 significant digits, exponent when needed.
std::string number(double v) {
    if (!std::isfinite(v)) return std::isnan(v) ? "nan" : (v > 0 ? "inf" : "-inf");
    const double a = std::fabs(v);
    if (a != 0.0 && (a < 1e-3 || a >= 1e5)) return fmt::format("{:.3e}", v);
    return fmt::format("{:.4g}", v);
}

std::string withUnit(double v, const std::string& unit) {
    return unit.empty() ? number(v) : number(v) + " " + unit;
}

// Text in a Markdown table cell: a '|' would end the cell.
std::string cell(const std::string& text) {
    std::string out;
    for (char c : text) out += c == '|' ? std::string("\\|") : std::string(1, c);
    return out;
}

// A CSV field: quoted when it holds a comma or a quote.
std::string csvField(const std::string& text) {
    if (text.find_first_of(",\"\n") == std::string::npos) return text;
    std::string quoted = "\"";
    for (char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
    return quoted + "\"";
}

void writeCaseCsv(const fs::path& file, const CaseResult& result) {
    std::ostringstream out;
    out << "series,x_name,x,y_name,y\n";
    for (const CaseResult::Column& c : result.data)
        for (std::size_t k = 0; k < c.x.size() && k < c.y.size(); ++k)
            out << csvField(c.series) << ',' << csvField(c.xName) << ','
                << fmt::format("{:.9g}", c.x[k]) << ',' << csvField(c.yName) << ','
                << fmt::format("{:.9g}", c.y[k]) << '\n';
    writeFileAtomically(file, [&](std::ostream& o) { o << out.str(); });
}

std::string markdownSummary(const std::vector<CaseResult>& results, const Options& options,
                            const plot::Result& plots) {
    std::ostringstream md;
    const auto failed = std::count_if(results.begin(), results.end(),
                                      [](const CaseResult& r) { return !r.passed(); });
    md << "# pbf validate" << (options.quick ? " --quick" : "") << "\n\n";
    md << fmt::format("pbf {}; {} cases, {} passed, {} failed.\n\n", kVersion, results.size(),
                      results.size() - std::size_t(failed), failed);
    if (!plots.drawn) md << "Plots: not drawn (" << plots.message << ").\n\n";
    md << "| case | metric | value | reference | tolerance | result |\n";
    md << "| --- | --- | --- | --- | --- | --- |\n";
    for (const CaseResult& r : results)
        for (const Check& c : r.checks)
            md << fmt::format("| {} | {} | {} | {} | {} | {} |\n", r.name, cell(c.metric),
                              withUnit(c.value, c.unit), withUnit(c.reference, c.unit), c.limit(),
                              c.passed() ? "pass" : "**FAIL**");
    for (const CaseResult& r : results) {
        md << "\n## " << r.name << ": " << r.title << "\n\n";
        md << fmt::format("{} ({:.1f} s). Plot: [{}.png]({}.png), data: [{}.csv]({}.csv).\n\n",
                          r.passed() ? "Passed" : "**Failed**", r.wallSeconds, r.name, r.name,
                          r.name, r.name);
        if (!r.notes.empty()) md << r.notes << "\n\n";
        md << "| metric | value | reference | tolerance | reference from | why this tolerance |\n";
        md << "| --- | --- | --- | --- | --- | --- |\n";
        for (const Check& c : r.checks)
            md << fmt::format("| {} | {} | {} | {} | {} | {} |\n", cell(c.metric),
                              withUnit(c.value, c.unit), withUnit(c.reference, c.unit), c.limit(),
                              cell(c.source), cell(c.why));
    }
    return md.str();
}

}  // namespace

bool Check::passed() const {
    // NaN fails every comparison: a measurement that could not be made is not a pass.
    switch (bound) {
        case Bound::AtLeast:
            return value >= reference - tolerance;
        case Bound::AtMost:
            return value <= reference + tolerance;
        case Bound::Within:
            break;
    }
    return std::fabs(value - reference) <= tolerance;
}

std::string Check::limit() const {
    switch (bound) {
        case Bound::AtLeast:
            return ">= " + withUnit(reference - tolerance, unit);
        case Bound::AtMost:
            return "<= " + withUnit(reference + tolerance, unit);
        case Bound::Within:
            break;
    }
    return "± " + withUnit(tolerance, unit);
}

bool CaseResult::passed() const {
    return !checks.empty() &&
           std::all_of(checks.begin(), checks.end(), [](const Check& c) { return c.passed(); });
}

std::string formatTable(const std::vector<CaseResult>& results) {
    struct Row {
        std::string cells[6];
    };
    std::vector<Row> rows{{{"case", "metric", "value", "reference", "tolerance", "result"}}};
    for (const CaseResult& r : results)
        for (const Check& c : r.checks)
            rows.push_back(
                {{r.name, c.metric, withUnit(c.value, c.unit), withUnit(c.reference, c.unit),
                  c.limit(), c.passed() ? "pass" : "FAIL"}});
    std::size_t width[6] = {};
    for (const Row& row : rows)
        for (int k = 0; k < 6; ++k) width[k] = std::max(width[k], row.cells[k].size());
    std::ostringstream out;
    for (std::size_t i = 0; i < rows.size(); ++i) {
        for (int k = 0; k < 6; ++k)
            out << fmt::format("{:<{}}", rows[i].cells[k], width[k]) << (k < 5 ? "  " : "\n");
        if (i == 0) {
            for (int k = 0; k < 6; ++k) out << std::string(width[k], '-') << (k < 5 ? "  " : "\n");
        }
    }
    return out.str();
}

plot::Result writeReport(const fs::path& directory, const std::vector<CaseResult>& results,
                         const Options& options) {
    std::error_code ec;
    fs::create_directories(directory, ec);
    if (ec || !fs::is_directory(directory))
        throw IoError(directory.string() + ": cannot create the report directory" +
                      (ec ? " (" + ec.message() + ")" : ""));
    std::vector<plot::Job> jobs;
    for (const CaseResult& r : results) {
        writeCaseCsv(directory / (r.name + ".csv"), r);
        jobs.push_back({r.figure, directory / (r.name + ".png")});
    }
    const plot::Result plots = plot::drawFigures(jobs);
    writeFileAtomically(directory / "summary.md", [&](std::ostream& out) {
        out << markdownSummary(results, options, plots);
    });
    return plots;
}

}  // namespace pbf::validation
