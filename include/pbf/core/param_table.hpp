// The one table of simulation parameters.
//
// Every field of SimulationParams (include/pbf/core/params.hpp) has one row here:
// its path in scene files, its member, unit, valid range, whether it may
// change while a World runs, and a one-line description. The default is the
// member's initializer (read from a default SimulationParams, never copied).
// The table drives everything that handles parameters one by one:
//   - reading scene files and their error messages (io/scene.cpp),
//   - validate(SimulationParams) (core/params.cpp),
//   - Python's `world.settings` and the FluidParams / SolverParams /
//     ArtificialPressureParams / SimulationParams classes (python/src),
//   - `pbf params` and the parameter table of docs/scenes.md (a test fails
//     when the doc and the table differ).
// Adding a parameter: a member with its default in params.hpp and a row in
// src/core/param_table.cpp (docs/architecture.md, "How to add ...").
#pragma once

#include <span>
#include <string>
#include <string_view>
#include <variant>

#include "pbf/core/params.hpp"

namespace pbf {

// The struct of SimulationParams a parameter is a member of.
enum class ParamGroup { Simulation, Fluid, Solver, ArtificialPressure };

// A parameter's value; the alternative is the member's type.
using ParamValue = std::variant<float, int, Vec3, Aabb, TimeStepMode>;

enum class ParamType { Float, Int, Vec3, Box, Choice };

// [lo, hi], with open ends where marked. For a Vec3 the bound is on its
// length (hi only); boxes and choices have none.
struct ParamRange {
    double lo = 0.0;
    double hi = 0.0;
    bool loOpen = false;
    bool hiOpen = false;
    // The upper bound is another parameter's value (its path), e.g.
    // solver.min_iterations <= solver.max_iterations.
    std::string_view hiParam = {};
};

struct ParamInfo {
    std::string_view path;       // as in scene files and messages: "solver.iterations"
    std::string_view attribute;  // Python `world.settings` attribute: "iterations"
    ParamGroup group;
    ParamType type;
    std::string_view unit;  // SI, as docs print it ("m/s²"); "1": dimensionless; "": a count
    ParamRange range;
    bool live;      // may change while a World runs (World::applySettings)
    bool required;  // scene files must give it (no default)
    std::string_view description;
    // Docs' texts where the range or the default says more than numbers
    // ("" = from `range` / the default SimulationParams).
    std::string_view rangeText = {};
    std::string_view defaultText = {};

    ParamValue (*getIn)(const void* group) = nullptr;
    void (*setIn)(void* group, const ParamValue& value) = nullptr;

    // The last part of the path: the member's name in its group's Python class.
    std::string_view name() const;
    ParamValue get(const SimulationParams& params) const;
    // `value` must hold the parameter's type (std::bad_variant_access otherwise).
    void set(SimulationParams& params, const ParamValue& value) const;
    // "" when the value in `params` is in range, else "path: problem" (the
    // message validate() returns).
    std::string check(const SimulationParams& params) const;
};

// The rows, in the order scene files and docs list them.
std::span<const ParamInfo> paramTable();
// The row of a scene path or a Python attribute name; null when none.
const ParamInfo* findParam(std::string_view pathOrAttribute);

// The group struct a row's accessors take, inside `params`.
const void* groupIn(const SimulationParams& params, ParamGroup group);
void* groupIn(SimulationParams& params, ParamGroup group);

// The names of TimeStepMode's values ("adaptive", "fixed"): the Choice type.
std::string_view timeStepName(TimeStepMode mode);
// Throws std::invalid_argument "expected \"adaptive\" or \"fixed\", got \"x\"".
TimeStepMode parseTimeStepName(std::string_view name);

// Texts for docs and `pbf params`: the range as "[1, 100]", the default of
// a default SimulationParams, a value as scene files write it.
std::string rangeText(const ParamInfo& param);
std::string defaultText(const ParamInfo& param);
std::string valueText(const ParamValue& value);
// The Markdown table of docs/scenes.md's "Simulation parameters":
// | field | unit | default | valid range | live | meaning |
std::string paramTableMarkdown();

}  // namespace pbf
