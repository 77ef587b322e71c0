// Shared by every translation unit of the _pbf extension: the conversions
// that must be identical everywhere (a type caster or an opaque container
// seen differently by two files would break the one-definition rule) and
// the functions that add each concept's bindings to the module.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl_bind.h>

#include <charconv>
#include <cmath>
#include <cstdlib>
#include <initializer_list>
#include <string>
#include <vector>

#include "pbf/core/param_table.hpp"
#include "pbf/core/params.hpp"
#include "pbf/core/vec3.hpp"
#include "pbf/world/world_def.hpp"

// The definition's lists are bound as opaque Python lists (py::bind_vector)
// so that `definition.fluid_blocks.append(block)` changes the definition;
// with pybind11's default conversion it would change a temporary copy.
PYBIND11_MAKE_OPAQUE(std::vector<pbf::FluidBlock>)
PYBIND11_MAKE_OPAQUE(std::vector<pbf::SolidDescription>)
PYBIND11_MAKE_OPAQUE(std::vector<pbf::EmitterDescription>)
PYBIND11_MAKE_OPAQUE(std::vector<pbf::OutletDescription>)
PYBIND11_MAKE_OPAQUE(std::vector<pbf::RigidBodyDescription>)

namespace pbf::python {

// A float parameter as a Python float: the double with the shortest decimal
// that reads back as the same float (0.01f gives 0.01, not
// 0.009999999776482582), so that what Python shows is what was written in
// the scene, and converting it back to float gives the same bits.
inline double shortestDouble(float value) {
    if (!std::isfinite(value)) return value;
    char text[32];
    const auto end = std::to_chars(text, text + sizeof text, value).ptr;
    *end = '\0';
    const double parsed = std::strtod(text, nullptr);
    return static_cast<float>(parsed) == value ? parsed : double(value);
}

}  // namespace pbf::python

namespace pybind11::detail {

// pbf::Vec3 <-> Python: any sequence of three numbers (tuple, list, numpy
// array) converts to a Vec3; a Vec3 comes back as a tuple of three floats.
// A caster rather than a bound class, so that `settings.gravity = (0, -9.81, 0)`
// and `numpy.array([0, -9.81, 0])` both work and no Python object aliases
// C++ memory that the World may replace.
template <>
struct type_caster<pbf::Vec3> {
    PYBIND11_TYPE_CASTER(pbf::Vec3, const_name("tuple[float, float, float]"));

    bool load(handle source, bool convert) {
        if (!source || isinstance<str>(source) || isinstance<bytes>(source) ||
            PySequence_Check(source.ptr()) != 1)
            return false;
        const auto items = reinterpret_borrow<sequence>(source);
        if (items.size() != 3) return false;
        float xyz[3];
        for (std::size_t k = 0; k < 3; ++k) {
            make_caster<float> component;
            if (!component.load(items[k], convert)) return false;
            xyz[k] = cast_op<float>(component);
        }
        value = {xyz[0], xyz[1], xyz[2]};
        return true;
    }

    static handle cast(const pbf::Vec3& v, return_value_policy, handle) {
        using pbf::python::shortestDouble;
        return make_tuple(shortestDouble(v.x), shortestDouble(v.y), shortestDouble(v.z)).release();
    }
};

}  // namespace pybind11::detail

namespace pbf::python {

namespace py = pybind11;

void bindErrors(py::module_& m);           // errors.cpp
void bindParams(py::module_& m);           // params.cpp
void bindDefinition(py::module_& m);       // definition.cpp
void bindBodyDescription(py::module_& m);  // bodies.cpp: pbf.RigidBodyDescription
void bindSettings(py::module_& m);         // settings.cpp
void bindWorld(py::module_& m);            // world.cpp
void bindRun(py::module_& m);              // run.cpp

// A parameter's value as Python shows it (floats through shortestDouble,
// "solver.time_step" as its name), and a Python value as the parameter's
// type (TypeError naming the parameter's path when it does not convert;
// SceneError for an unknown time step name).
py::object paramToPython(const ParamValue& value);
ParamValue paramFromPython(const ParamInfo& param, const py::handle& value);

// Getter and setter of a float field, shown through shortestDouble:
// .def_property("cfl", floatGetter(&SolverParams::cfl), floatSetter(&SolverParams::cfl)).
template <class C>
auto floatGetter(float C::*member) {
    return [member](const C& c) { return shortestDouble(c.*member); };
}
template <class C>
auto floatSetter(float C::*member) {
    return [member](C& c, float value) { c.*member = value; };
}

// "Type(a=1, b=(0.0, 1.0, 0.0))" from the Python attributes `fields` of `self`.
std::string reprOf(py::handle self, const char* type, std::initializer_list<const char*> fields);
std::string reprOf(py::handle self, const char* type, const std::vector<std::string>& fields);

}  // namespace pbf::python
