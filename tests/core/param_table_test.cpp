// The parameter table drives scene reading, validation and the docs: each
// test walks every row, so a row that one of them forgets fails here.
#include "pbf/core/param_table.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>

#include "pbf/io/scene.hpp"
#include "support/test_util.hpp"

namespace {

using pbf::ParamInfo;
using pbf::ParamType;
using pbf::ParamValue;

// A value of the row's type inside its range and different from its
// default (the midpoint of a numeric range; the other time step mode).
ParamValue otherValidValue(const ParamInfo& p) {
    const pbf::SimulationParams defaults;
    const double hi = p.range.hiParam.empty()
                          ? p.range.hi
                          : std::get<int>(pbf::findParam(p.range.hiParam)->get(defaults));
    switch (p.type) {
        case ParamType::Float: {
            const float mid = float(0.5 * (p.range.lo + hi));
            return mid != std::get<float>(p.get(defaults)) ? mid
                                                           : float(0.25 * p.range.lo + 0.75 * hi);
        }
        case ParamType::Int: {
            const int mid = int((p.range.lo + hi) / 2);
            return mid != std::get<int>(p.get(defaults)) ? mid : mid + 1;
        }
        case ParamType::Vec3:
            return pbf::Vec3{0.5f, -3.0f, 0.25f};
        case ParamType::Box:
            return pbf::Aabb{{-0.5f, 0.0f, 0.0f}, {1.5f, 2.0f, 1.25f}};
        case ParamType::Choice:
            return std::get<pbf::TimeStepMode>(p.get(defaults)) == pbf::TimeStepMode::Adaptive
                       ? pbf::TimeStepMode::Fixed
                       : pbf::TimeStepMode::Adaptive;
    }
    return {};
}

std::string jsonOf(const ParamValue& v) {
    return pbf::valueText(v);
}

// Rows whose value changes the particle count or the grid of the small
// scene; they are read like the others but need values the scene fits.
bool shapesTheScene(const ParamInfo& p) {
    return p.path == "particle_radius" || p.path == "solver.kernel_radius_factor";
}

TEST(ParamTable, EveryRowIsReadFromSceneFilesAtItsPath) {
    for (const ParamInfo& p : pbf::paramTable()) {
        if (shapesTheScene(p)) continue;
        const ParamValue value = otherValidValue(p);
        const pbf::Scene scene = pbf::parseScene(pbf::test::smallSceneJson(), "small.json",
                                                 {{std::string(p.path), jsonOf(value)}});
        EXPECT_EQ(jsonOf(p.get(scene.simulation)), jsonOf(value)) << p.path;
    }
    // The radius and kernel factor too, with values the small scene fits.
    const pbf::Scene scene =
        pbf::parseScene(pbf::test::smallSceneJson(), "small.json",
                        {{"particle_radius", "0.015"}, {"solver.kernel_radius_factor", "3.5"}});
    EXPECT_FLOAT_EQ(scene.simulation.particleRadius, 0.015f);
    EXPECT_FLOAT_EQ(scene.simulation.solver.kernelRadiusFactor, 3.5f);
}

TEST(ParamTable, EveryNumericRowIsValidatedAgainstItsRange) {
    for (const ParamInfo& p : pbf::paramTable()) {
        if (p.type != ParamType::Float && p.type != ParamType::Int) continue;
        // Just beyond the upper bound (the upper bound of min_iterations is
        // max_iterations' default).
        const double hi = p.range.hiParam.empty() ? p.range.hi : 100.0;
        const std::string beyond =
            p.type == ParamType::Int ? std::to_string(int(hi) + 1) : std::to_string(hi * 1.5 + 1.0);
        try {
            pbf::parseScene(pbf::test::smallSceneJson(), "bad.json",
                            {{std::string(p.path), beyond}});
            ADD_FAILURE() << p.path << " = " << beyond << " was accepted";
        } catch (const pbf::SceneError& e) {
            const std::string expected = "bad.json: " + std::string(p.path) + ": must be in ";
            EXPECT_EQ(std::string(e.what()).rfind(expected, 0), 0u) << e.what();
        }
    }
}

// Each row reads and writes its own member: writing one row changes no
// other row's value. A row bound to another row's member (the table says
// every member has one row, so a wrong binding is always such a pair) is
// caught here, where reading back through the same row cannot catch it.
TEST(ParamTable, WritingARowChangesOnlyThatRow) {
    const pbf::SimulationParams defaults;
    for (const ParamInfo& p : pbf::paramTable()) {
        pbf::SimulationParams params = defaults;
        const ParamValue value = otherValidValue(p);
        p.set(params, value);
        EXPECT_EQ(jsonOf(p.get(params)), jsonOf(value)) << p.path;
        for (const ParamInfo& q : pbf::paramTable()) {
            if (&q == &p) continue;
            EXPECT_EQ(jsonOf(q.get(params)), jsonOf(q.get(defaults)))
                << "writing " << p.path << " changed " << q.path
                << ": the two rows are bound to the same member";
        }
    }
}

// A value written as a bound is in range: a float row compares its member
// (the value rounded to float) with the bound rounded the same way
// (particle_radius = 1e-5 was refused as "must be in [1e-05, 1], got 1e-05").
TEST(ParamTable, EveryNumericRowAcceptsItsClosedBounds) {
    for (const ParamInfo& p : pbf::paramTable()) {
        if ((p.type != ParamType::Float && p.type != ParamType::Int) || !p.range.hiParam.empty())
            continue;
        for (const auto& [bound, open] :
             {std::pair{p.range.lo, p.range.loOpen}, std::pair{p.range.hi, p.range.hiOpen}}) {
            if (open) continue;
            pbf::SimulationParams params;
            if (p.type == ParamType::Float)
                p.set(params, float(bound));
            else
                p.set(params, int(bound));
            EXPECT_EQ(p.check(params), "") << p.path << " = " << bound;
        }
    }
    const pbf::Scene scene =
        pbf::parseScene(pbf::test::smallSceneJson(), "small.json", {{"solver.relaxation", "1e-6"}});
    EXPECT_FLOAT_EQ(scene.simulation.solver.relaxation, 1e-6f);
}

TEST(ParamTable, DefaultsAreValidAndRowsAreUnique) {
    EXPECT_EQ(pbf::validate(pbf::SimulationParams{}), "");
    for (const ParamInfo& p : pbf::paramTable()) {
        EXPECT_EQ(pbf::findParam(p.path), &p);
        EXPECT_EQ(pbf::findParam(p.attribute), &p) << p.attribute;
        EXPECT_EQ(p.check(pbf::SimulationParams{}), "") << p.path;
    }
}

// docs/scenes.md holds the table between two markers; `pbf params
// --markdown` prints what belongs there.
TEST(ParamTable, DocsSceneTableIsTheTable) {
    std::ifstream in(std::string(PBF_SOURCE_DIR) + "/docs/scenes.md");
    ASSERT_TRUE(in) << "docs/scenes.md";
    std::stringstream text;
    text << in.rdbuf();
    const std::string doc = text.str();
    const std::string begin = "<!-- parameter table: pbf params --markdown -->\n";
    const std::string end = "<!-- end of parameter table -->";
    const std::size_t from = doc.find(begin);
    const std::size_t to = doc.find(end);
    ASSERT_NE(from, std::string::npos) << "no marker: " << begin;
    ASSERT_NE(to, std::string::npos) << "no marker: " << end;
    EXPECT_EQ(doc.substr(from + begin.size(), to - from - begin.size()), pbf::paramTableMarkdown())
        << "docs/scenes.md's parameter table differs from the table: paste the output of "
           "`pbf params --markdown` between the markers";
}

}  // namespace
