// `pbf validate`'s verdicts and report: a check passes only inside its
// bound (NaN never passes), a case passes only when every check does, and
// the report holds the table, the CSV data and the tolerances' reasons.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "pbf/validate/validate.hpp"

namespace pbf::validation {
namespace {

Check check(double value, double reference, double tolerance,
            Check::Bound bound = Check::Bound::Within) {
    Check c;
    c.metric = "m";
    c.value = value;
    c.reference = reference;
    c.tolerance = tolerance;
    c.bound = bound;
    return c;
}

TEST(ValidationCheck, WithinAtLeastAtMost) {
    EXPECT_TRUE(check(1.05, 1.0, 0.1).passed());
    EXPECT_TRUE(check(0.95, 1.0, 0.1).passed());
    EXPECT_FALSE(check(1.2, 1.0, 0.1).passed());
    EXPECT_FALSE(check(0.8, 1.0, 0.1).passed());
    EXPECT_TRUE(check(5.0, 1.0, 0.0, Check::Bound::AtLeast).passed());
    EXPECT_FALSE(check(0.9, 1.0, 0.0, Check::Bound::AtLeast).passed());
    EXPECT_TRUE(check(0.5, 1.0, 0.0, Check::Bound::AtMost).passed());
    EXPECT_FALSE(check(1.5, 1.0, 0.0, Check::Bound::AtMost).passed());
    const double nan = std::numeric_limits<double>::quiet_NaN();
    for (Check::Bound b : {Check::Bound::Within, Check::Bound::AtLeast, Check::Bound::AtMost})
        EXPECT_FALSE(check(nan, 1.0, 10.0, b).passed()) << "a measurement that failed passed";
    EXPECT_EQ(check(0.5, 1.0, 0.25, Check::Bound::AtLeast).limit(), ">= 0.75");
}

TEST(ValidationCase, PassesOnlyWhenEveryCheckDoes) {
    CaseResult r;
    EXPECT_FALSE(r.passed()) << "a case without checks checked nothing";
    r.checks = {check(1.0, 1.0, 0.1), check(2.0, 2.0, 0.1)};
    EXPECT_TRUE(r.passed());
    r.checks.push_back(check(3.0, 2.0, 0.1));
    EXPECT_FALSE(r.passed());
}

TEST(ValidationReport, TableCsvAndSummary) {
    CaseResult r;
    r.name = "example";
    r.title = "An example";
    Check ok = check(1.02, 1.0, 0.05);
    ok.metric = "ratio | with a bar";
    ok.source = "a closed form";
    ok.why = "because";
    r.checks = {ok, check(2.0, 1.0, 0.5)};
    r.data.push_back({"series, with comma", "t", "y", {0.0, 1.0}, {2.0, 3.5}});
    r.figure.title = "An example";
    r.figure.panels.push_back({"p", "t (s)", "y (m)", {{"s", {0.0, 1.0}, {2.0, 3.5}}}});
    const std::string table = formatTable({r});
    EXPECT_NE(table.find("example  ratio | with a bar"), std::string::npos) << table;
    EXPECT_NE(table.find("pass"), std::string::npos);
    EXPECT_NE(table.find("FAIL"), std::string::npos);

    const auto dir = std::filesystem::temp_directory_path() / "pbf_validation_report_test";
    std::filesystem::remove_all(dir);
    // Without matplotlib (a Python without site-packages) the report is
    // still written and the result says what to install.
    ::setenv("PBF_PYTHON", PBF_TESTS_DATA_DIR "/python3_without_site_packages.sh", 1);
    const plot::Result plots = writeReport(dir, {r}, Options{});
    ::unsetenv("PBF_PYTHON");
    EXPECT_FALSE(plots.drawn);
    EXPECT_TRUE(plots.missingDependency) << plots.message;
    std::ifstream csv(dir / "example.csv");
    std::stringstream csvText;
    csvText << csv.rdbuf();
    EXPECT_EQ(csvText.str(),
              "series,x_name,x,y_name,y\n\"series, with comma\",t,0,y,2\n"
              "\"series, with comma\",t,1,y,3.5\n");
    std::ifstream md(dir / "summary.md");
    std::stringstream mdText;
    mdText << md.rdbuf();
    const std::string summary = mdText.str();
    EXPECT_NE(summary.find("1 cases, 0 passed, 1 failed"), std::string::npos) << summary;
    EXPECT_NE(summary.find("ratio \\| with a bar"), std::string::npos) << summary;
    EXPECT_NE(summary.find("| a closed form | because |"), std::string::npos) << summary;
    EXPECT_NE(summary.find("Plots: not drawn"), std::string::npos) << summary;
    EXPECT_TRUE(std::filesystem::exists(dir / "example.plot.json"));
    std::filesystem::remove_all(dir);
}

TEST(ValidationCases, AllRegisteredWithUniqueNames) {
    std::vector<std::string> names;
    for (const Case& c : cases()) {
        EXPECT_FALSE(c.description.empty()) << c.name;
        EXPECT_TRUE(c.run) << c.name;
        EXPECT_EQ(std::count(names.begin(), names.end(), c.name), 0) << c.name;
        names.push_back(c.name);
    }
    EXPECT_EQ(names,
              (std::vector<std::string>{
                  "martin_moyce", "hydrostatic", "free_fall", "momentum", "taylor_green",
                  "archimedes", "heave", "rayleigh_drop", "cube_to_sphere", "laplace", "wetting",
                  "pinch_off", "open_channel", "standing_wave", "wave_maker", "sloshing"}));
}

// The observed order is the slope of log error against log h; the study
// passes when the finest error is below the coarsest; the report holds the
// table and the CSV. Catches a slope of the wrong sign or base, a "falls"
// that compares the wrong ends, and a study missing from the report.
TEST(ValidationConvergence, OrderFallsAndReport) {
    Convergence second{"e", "h (mm)", {4.0, 2.0, 1.0}, {0.16, 0.04, 0.01}};
    EXPECT_NEAR(second.order(), 2.0, 1e-12);
    EXPECT_TRUE(second.falls());
    const Check ok = convergenceCheck(second, "why");
    EXPECT_TRUE(ok.passed());
    EXPECT_NEAR(ok.value, 0.0625, 1e-12);
    Convergence rising{"r", "h (mm)", {4.0, 2.0, 1.0}, {0.01, 0.02, 0.04}};
    EXPECT_NEAR(rising.order(), -1.0, 1e-12);
    EXPECT_FALSE(rising.falls());
    EXPECT_FALSE(convergenceCheck(rising, "why").passed());
    Convergence one{"o", "h", {1.0}, {0.5}};
    EXPECT_TRUE(std::isnan(one.order()));
    EXPECT_FALSE(one.falls());
    EXPECT_FALSE(convergenceCheck(one, "why").passed()) << "one resolution shows no convergence";

    CaseResult r;
    r.name = "study";
    r.checks = {ok};
    r.convergence = {second, rising};
    const std::string table = formatConvergenceTable({r});
    EXPECT_NE(table.find("0.16 (4), 0.04 (2), 0.01 (1)"), std::string::npos) << table;
    EXPECT_NE(table.find("NO"), std::string::npos) << table;
    const auto dir = std::filesystem::temp_directory_path() / "pbf_validation_convergence_test";
    std::filesystem::remove_all(dir);
    ::setenv("PBF_PYTHON", PBF_TESTS_DATA_DIR "/python3_without_site_packages.sh", 1);
    writeReport(dir, {r}, Options{});
    ::unsetenv("PBF_PYTHON");
    std::ifstream csv(dir / "convergence.csv");
    std::stringstream text;
    text << csv.rdbuf();
    EXPECT_NE(text.str().find("study,e,h (mm),1,0.01"), std::string::npos) << text.str();
    std::ifstream summary(dir / "summary.md");
    std::stringstream md;
    md << summary.rdbuf();
    EXPECT_NE(md.str().find("## Convergence"), std::string::npos);
    std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace pbf::validation
