// The table, the CSV files and the Markdown summary of `pbf validate`.
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
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

// The errors of a study, coarse to fine: "0.032 (10), 0.016 (5)".
std::string errorsText(const Convergence& c) {
    std::string text;
    for (std::size_t k = 0; k < c.error.size() && k < c.h.size(); ++k)
        text += (k ? ", " : "") + fmt::format("{} ({:g})", number(c.error[k]), c.h[k]);
    return text;
}

bool anyConvergence(const std::vector<CaseResult>& results) {
    return std::any_of(results.begin(), results.end(),
                       [](const CaseResult& r) { return !r.convergence.empty(); });
}

void writeConvergenceCsv(const fs::path& file, const std::vector<CaseResult>& results) {
    std::ostringstream out;
    out << "case,metric,resolution,h,error\n";
    for (const CaseResult& r : results)
        for (const Convergence& c : r.convergence)
            for (std::size_t k = 0; k < c.h.size() && k < c.error.size(); ++k)
                out << csvField(r.name) << ',' << csvField(c.metric) << ','
                    << csvField(c.resolution) << ',' << fmt::format("{:.9g}", c.h[k]) << ','
                    << fmt::format("{:.9g}", c.error[k]) << '\n';
    writeFileAtomically(file, [&](std::ostream& o) { o << out.str(); });
}

// One log-log panel per case: every study's error against h.
plot::Figure convergenceFigure(const std::vector<CaseResult>& results) {
    plot::Figure figure{"Convergence: error against resolution (log-log)", {}, 2};
    for (const CaseResult& r : results) {
        if (r.convergence.empty()) continue;
        plot::Panel panel{r.name, r.convergence.front().resolution, "error", {}};
        panel.logX = panel.logY = true;
        for (const Convergence& c : r.convergence)
            panel.series.push_back({fmt::format("{} (order {:.2f})", c.metric, c.order()), c.h,
                                    c.error, plot::Style::Line});
        figure.panels.push_back(std::move(panel));
    }
    return figure;
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
    if (anyConvergence(results)) {
        md << "\n## Convergence\n\nEvery study's error at its resolutions, coarse to fine (the "
              "resolution in brackets), the observed order (the slope of log error against log "
              "h) and whether the error falls. Plot: [convergence.png](convergence.png), data: "
              "[convergence.csv](convergence.csv).\n\n";
        md << "| case | error | resolution | errors, coarse to fine | observed order | falls |\n";
        md << "| --- | --- | --- | --- | --- | --- |\n";
        for (const CaseResult& r : results)
            for (const Convergence& c : r.convergence)
                md << fmt::format("| {} | {} | {} | {} | {} | {} |\n", r.name, cell(c.metric),
                                  cell(c.resolution), errorsText(c), number(c.order()),
                                  c.falls() ? "yes" : "**no**");
    }
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

double Convergence::order() const {
    std::vector<double> x, y;
    for (std::size_t k = 0; k < h.size() && k < error.size(); ++k)
        if (h[k] > 0.0 && error[k] > 0.0) {
            x.push_back(std::log(h[k]));
            y.push_back(std::log(error[k]));
        }
    if (x.size() < 2) return std::numeric_limits<double>::quiet_NaN();
    double mx = 0.0, my = 0.0;
    for (std::size_t k = 0; k < x.size(); ++k) {
        mx += x[k] / double(x.size());
        my += y[k] / double(x.size());
    }
    double sxy = 0.0, sxx = 0.0;
    for (std::size_t k = 0; k < x.size(); ++k) {
        sxy += (x[k] - mx) * (y[k] - my);
        sxx += (x[k] - mx) * (x[k] - mx);
    }
    return sxx > 0.0 ? sxy / sxx : std::numeric_limits<double>::quiet_NaN();
}

bool Convergence::falls() const {
    // NaN compares false: an error that could not be measured does not fall.
    return error.size() >= 2 && error.back() < error.front();
}

Check convergenceCheck(const Convergence& study, const std::string& why) {
    const double ratio = study.error.size() >= 2 && study.error.front() > 0.0
                             ? study.error.back() / study.error.front()
                             : std::numeric_limits<double>::quiet_NaN();
    return {fmt::format("error falls: {}, finest / coarsest (order {:.2f})", study.metric,
                        study.order()),
            ratio,
            0.0,
            1.0,
            "",
            "convergence: the error must fall as the particles get smaller",
            why,
            Check::Bound::AtMost};
}

std::string formatConvergenceTable(const std::vector<CaseResult>& results) {
    std::vector<std::array<std::string, 5>> rows{
        {"case", "error", "errors, coarse to fine (resolution)", "order", "falls"}};
    for (const CaseResult& r : results)
        for (const Convergence& c : r.convergence)
            rows.push_back(
                {r.name, c.metric, errorsText(c), number(c.order()), c.falls() ? "yes" : "NO"});
    std::size_t width[5] = {};
    for (const auto& row : rows)
        for (int k = 0; k < 5; ++k) width[k] = std::max(width[k], row[std::size_t(k)].size());
    std::ostringstream out;
    for (std::size_t i = 0; i < rows.size(); ++i) {
        for (int k = 0; k < 5; ++k)
            out << fmt::format("{:<{}}", rows[i][std::size_t(k)], width[k])
                << (k < 4 ? "  " : "\n");
        if (i == 0)
            for (int k = 0; k < 5; ++k) out << std::string(width[k], '-') << (k < 4 ? "  " : "\n");
    }
    return out.str();
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
    if (anyConvergence(results)) {
        writeConvergenceCsv(directory / "convergence.csv", results);
        jobs.push_back({convergenceFigure(results), directory / "convergence.png"});
    }
    const plot::Result plots = plot::drawFigures(jobs);
    writeFileAtomically(directory / "summary.md", [&](std::ostream& out) {
        out << markdownSummary(results, options, plots);
    });
    return plots;
}

}  // namespace pbf::validation
