// `pbf validate`: the physics checked against experiments and closed forms.
//
// Each case builds worlds in code (pbf::World, the same frame loop as every
// driver; no solver code of its own), measures what it compares, and
// returns checks: a value, the reference it is compared with, the tolerance
// and the reason for that tolerance. A case passes when every check does.
// writeReport() writes a directory with one CSV (the measured series) and
// one PNG plot (the plotting path of include/pbf/run/plot.hpp) per case and a
// Markdown summary. docs/validation.md describes every case and its sources.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "pbf/run/plot.hpp"

namespace pbf::validation {

// One compared quantity. Within (the default) passes when
// |value - reference| <= tolerance; AtLeast when value >= reference -
// tolerance; AtMost when value <= reference + tolerance.
struct Check {
    enum class Bound { Within, AtLeast, AtMost };
    std::string metric;  // what was measured, e.g. "surge front Z, RMS difference"
    double value = 0.0;
    double reference = 0.0;
    double tolerance = 0.0;
    std::string unit;    // of value, reference and tolerance ("" for ratios)
    std::string source;  // where the reference comes from
    std::string why;     // why this tolerance
    Bound bound = Bound::Within;
    bool passed() const;
    std::string limit() const;  // "± 0.1 m", ">= 0.5", "<= 0.02 m/s" for tables
};

struct CaseResult {
    std::string name;
    std::string title;
    std::vector<Check> checks;
    plot::Figure figure;  // drawn into <name>.png
    // The measured series, written as <name>.csv (columns series, x, y).
    struct Column {
        std::string series;
        std::string xName;
        std::string yName;
        std::vector<double> x;
        std::vector<double> y;
    };
    std::vector<Column> data;
    std::string notes;  // Markdown: setup and what to read from the plot
    double wallSeconds = 0.0;
    bool passed() const;
};

struct Options {
    bool quick = false;  // reduced resolutions: a few minutes on two cores
    // Progress messages ("martin_moyce: 40 particles across, T = 2.1"); may be empty.
    std::function<void(const std::string&)> progress;
};

struct Case {
    std::string name;         // on the command line, e.g. "martin_moyce"
    std::string description;  // one line
    std::function<CaseResult(const Options&)> run;
};

// Every case, in the order they run.
const std::vector<Case>& cases();

// The table printed by `pbf validate`: case, metric, value, reference,
// tolerance, pass/fail.
std::string formatTable(const std::vector<CaseResult>& results);

// Writes DIR/<case>.csv, DIR/summary.md and (through plot::drawFigures)
// DIR/<case>.png for every result; IoError naming the file when a write
// fails. Returns the plotting result (a missing matplotlib is reported, not
// thrown).
plot::Result writeReport(const std::filesystem::path& directory,
                         const std::vector<CaseResult>& results, const Options& options);

}  // namespace pbf::validation
