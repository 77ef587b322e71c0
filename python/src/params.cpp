// Simulation parameters (include/pbf/core/params.hpp) and the box type: the
// plain structs a definition is made of. Their attributes are the rows of
// the parameter table (include/pbf/core/param_table.hpp), named as in scene
// files, so `params.solver.iterations` in Python is "solver.iterations" in
// a scene and in error messages.
#include <pybind11/operators.h>

#include "bindings.hpp"

namespace pbf::python {
namespace {

// An Aabb from ((x0, y0, z0), (x1, y1, z1)) or a (2, 3) array.
Aabb aabbFromPair(const py::sequence& pair) {
    if (pair.size() != 2)
        throw py::value_error("Aabb: expected (min, max), two points of 3 numbers; got " +
                              std::to_string(pair.size()) + " items");
    return {pair[0].cast<Vec3>(), pair[1].cast<Vec3>()};
}

void bindAabb(py::module_& m) {
    py::class_<Aabb>(m, "Aabb", "Axis-aligned box [min, max] in metres.")
        .def(py::init([](const Vec3& min, const Vec3& max) {
                 return Aabb{min, max};
             }),
             py::arg("min"), py::arg("max"))
        .def(py::init(&aabbFromPair), py::arg("pair"),
             "From (min, max), e.g. ((0, 0, 0), (1, 1, 1)) or a (2, 3) array.")
        .def_readwrite("min", &Aabb::min)
        .def_readwrite("max", &Aabb::max)
        .def_property_readonly("extent", &Aabb::extent)
        .def_property_readonly("volume", [](const Aabb& b) { return shortestDouble(b.volume()); })
        .def("contains", &Aabb::contains, py::arg("point"))
        .def("__iter__", [](const Aabb& b) { return py::iter(py::make_tuple(b.min, b.max)); })
        .def(py::self == py::self)
        .def("__repr__", [](const py::object& self) {
            return reprOf(self, "Aabb", {"min", "max"});
        });
    // Every place that takes an Aabb also takes a pair of points.
    py::implicitly_convertible<py::tuple, Aabb>();
    py::implicitly_convertible<py::list, Aabb>();
    py::implicitly_convertible<py::array, Aabb>();
}

// What a parameter of each type must be, for conversion messages.
const char* expected(ParamType type) {
    switch (type) {
        case ParamType::Float:
            return "a number";
        case ParamType::Int:
            return "an integer";
        case ParamType::Vec3:
            return "three numbers";
        case ParamType::Box:
            return "a box (min, max)";
        case ParamType::Choice:
            return "a string";
    }
    return "a value";
}

// A row's docstring: its description, unit and range.
std::string docOf(const ParamInfo& p) {
    std::string doc(p.description);
    if (!p.unit.empty() && p.unit != "1") doc += "; " + std::string(p.unit);
    doc += "; " + rangeText(p);
    if (!p.live) doc += " (fixed while a world runs)";
    return doc;
}

// The parameters of one group as properties of its class, and the repr
// that lists them (after `extra`, the group's nested structs).
template <class Group>
void bindGroupParams(py::class_<Group>& cls, ParamGroup group, const char* name,
                     std::vector<std::string> fields) {
    for (const ParamInfo& p : paramTable()) {
        if (p.group != group) continue;
        const ParamInfo* param = &p;
        cls.def_property(
            std::string(p.name()).c_str(),
            [param](const Group& g) { return paramToPython(param->getIn(&g)); },
            [param](Group& g, const py::handle& value) {
                param->setIn(&g, paramFromPython(*param, value));
            },
            docOf(p).c_str());
        fields.emplace_back(p.name());
    }
    cls.def("__repr__",
            [name, fields](const py::object& self) { return reprOf(self, name, fields); });
}

void bindParamClasses(py::module_& m) {
    py::class_<FluidParams> fluid(m, "FluidParams", "Fluid material (docs/scenes.md, \"fluid\").");
    fluid.def(py::init<>());
    bindGroupParams(fluid, ParamGroup::Fluid, "FluidParams", {});

    py::class_<ArtificialPressureParams> pressure(
        m, "ArtificialPressureParams",
        "s_corr = -k (W(r) / W(dq h))^n (paper eq. 13-14), k in units of the constraint's scale.");
    pressure.def(py::init<>());
    bindGroupParams(pressure, ParamGroup::ArtificialPressure, "ArtificialPressureParams", {});

    py::class_<SolverParams> solver(m, "SolverParams",
                                    "Solver settings (docs/scenes.md, \"solver\").");
    solver.def(py::init<>())
        .def_readwrite("artificial_pressure", &SolverParams::artificialPressure);
    bindGroupParams(solver, ParamGroup::Solver, "SolverParams", {"artificial_pressure"});

    py::class_<SimulationParams> simulation(
        m, "SimulationParams", "Domain, gravity, particle radius, fluid and solver parameters.");
    simulation.def(py::init<>())
        .def_readwrite("fluid", &SimulationParams::fluid)
        .def_readwrite("solver", &SimulationParams::solver)
        .def_property_readonly(
            "particle_spacing",
            [](const SimulationParams& p) { return shortestDouble(p.particleSpacing()); })
        .def_property_readonly(
            "kernel_radius",
            [](const SimulationParams& p) { return shortestDouble(p.kernelRadius()); })
        .def(
            "validate", [](const SimulationParams& p) { return validate(p); },
            "\"\" when valid, else \"field: problem\" for the first invalid field.");
    bindGroupParams(simulation, ParamGroup::Simulation, "SimulationParams", {"fluid", "solver"});
}

}  // namespace

py::object paramToPython(const ParamValue& value) {
    struct ToPython {
        py::object operator()(float v) const { return py::float_(shortestDouble(v)); }
        py::object operator()(int v) const { return py::int_(v); }
        py::object operator()(const Vec3& v) const { return py::cast(v); }
        py::object operator()(const Aabb& v) const { return py::cast(v); }
        py::object operator()(TimeStepMode v) const {
            return py::str(std::string(timeStepName(v)));
        }
    };
    return std::visit(ToPython{}, value);
}

ParamValue paramFromPython(const ParamInfo& param, const py::handle& value) {
    try {
        switch (param.type) {
            case ParamType::Float:
                return value.cast<float>();
            case ParamType::Int:
                return value.cast<int>();
            case ParamType::Vec3:
                return value.cast<Vec3>();
            case ParamType::Box:
                return value.cast<Aabb>();
            case ParamType::Choice:
                break;
        }
        const std::string name = value.cast<std::string>();
        try {
            return parseTimeStepName(name);
        } catch (const std::invalid_argument& e) {
            throw SceneError(std::string(param.path) + ": " + e.what());
        }
    } catch (const py::cast_error&) {
        throw py::type_error(std::string(param.path) + ": expected " + expected(param.type) +
                             ", got " + py::repr(value).cast<std::string>());
    }
}

std::string reprOf(py::handle self, const char* type, const std::vector<std::string>& fields) {
    std::string text = std::string(type) + "(";
    const char* separator = "";
    for (const std::string& field : fields) {
        text += separator + field + "=" + py::repr(self.attr(field.c_str())).cast<std::string>();
        separator = ", ";
    }
    return text + ")";
}

std::string reprOf(py::handle self, const char* type, std::initializer_list<const char*> fields) {
    return reprOf(self, type, std::vector<std::string>(fields.begin(), fields.end()));
}

const char* typeName(ParamType type) {
    switch (type) {
        case ParamType::Float:
            return "float";
        case ParamType::Int:
            return "int";
        case ParamType::Vec3:
            return "vec3";
        case ParamType::Box:
            return "box";
        case ParamType::Choice:
            return "choice";
    }
    return "";
}

void bindParams(py::module_& m) {
    bindAabb(m);
    bindParamClasses(m);
    m.def(
        "parameters",
        [] {
            py::list rows;
            for (const ParamInfo& p : paramTable()) {
                py::dict row;
                row["path"] = std::string(p.path);
                row["attribute"] = std::string(p.attribute);
                row["type"] = typeName(p.type);
                row["unit"] = std::string(p.unit);
                row["default"] = paramToPython(p.get(SimulationParams{}));
                row["range"] = rangeText(p);
                row["min"] = p.range.lo;
                row["max"] = p.range.hiParam.empty()
                                 ? py::object(py::float_(p.range.hi))
                                 : py::object(py::str(std::string(p.range.hiParam)));
                row["min_open"] = p.range.loOpen;
                row["max_open"] = p.range.hiOpen;
                row["live"] = p.live;
                row["required"] = p.required;
                row["description"] = std::string(p.description);
                rows.append(row);
            }
            return rows;
        },
        "Every simulation parameter (the parameter table, docs/scenes.md): a list of dicts "
        "with path, attribute, type, unit, default, range (text), min, max (a number, or the "
        "path of the parameter that bounds it), min_open, max_open, live, required, "
        "description.");
}

}  // namespace pbf::python
