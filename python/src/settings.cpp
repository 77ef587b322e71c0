#include "settings.hpp"

#include <string>
#include <string_view>

#include "bindings.hpp"

namespace pbf::python {
namespace {

// What a setting's value must be, for conversions and their messages.
template <class T>
constexpr const char* kExpected = "a number";
template <>
constexpr const char* kExpected<int> = "an integer";
template <>
constexpr const char* kExpected<Vec3> = "three numbers";
template <>
constexpr const char* kExpected<std::string> = "a string";
template <>
constexpr const char* kExpected<Aabb> = "a box (min, max)";

template <class T>
T valueAs(const py::handle& value, const char* path) {
    try {
        return value.cast<T>();
    } catch (const py::cast_error&) {
        throw py::type_error(std::string(path) + ": expected " + kExpected<T> + ", got " +
                             py::repr(value).cast<std::string>());
    }
}

py::object toPython(float value) {
    return py::float_(shortestDouble(value));
}
template <class T>
py::object toPython(const T& value) {
    return py::cast(value);
}

// One live setting: its attribute name, its path in scene files (and in
// the library's messages) and how to read and write it in SimulationParams.
struct Field {
    const char* attribute;
    const char* path;
    const char* doc;
    py::object (*get)(const SimulationParams&);
    void (*set)(SimulationParams&, const py::handle&);
};

#define PBF_SETTING(attribute, path, type, member, doc)                                         \
    Field {                                                                                     \
        attribute, path, doc, [](const SimulationParams& p) { return toPython(p.member); },     \
            [](SimulationParams& p, const py::handle& v) { p.member = valueAs<type>(v, path); } \
    }

// The domain, particle radius and kernel radius factor are listed so that
// they can be read; writing them reaches applySettings, which refuses with
// "...: cannot change while the world runs".
const Field kFields[] = {
    PBF_SETTING("iterations", "solver.iterations", int, solver.iterations,
                "density iterations per substep, [1, 100]"),
    PBF_SETTING("relaxation", "solver.relaxation", float, solver.relaxation,
                "constraint-force-mixing epsilon, [1e-6, 10]"),
    PBF_SETTING("scorr_k", "solver.artificial_pressure.k", float, solver.artificialPressure.k,
                "artificial pressure s_corr k, [0, 1]"),
    PBF_SETTING("scorr_n", "solver.artificial_pressure.n", int, solver.artificialPressure.n,
                "artificial pressure s_corr n, [1, 8]"),
    PBF_SETTING("scorr_dq", "solver.artificial_pressure.dq", float, solver.artificialPressure.dq,
                "artificial pressure s_corr dq, fraction of h, (0, 1)"),
    Field{"time_step", "solver.time_step", "\"adaptive\" (CFL-limited) or \"fixed\"",
          [](const SimulationParams& p) {
              return py::object(py::str(timeStepName(p.solver.timeStepMode)));
          },
          [](SimulationParams& p, const py::handle& v) {
              p.solver.timeStepMode =
                  parseTimeStep(valueAs<std::string>(v, "solver.time_step"), "solver.time_step");
          }},
    PBF_SETTING("cfl", "solver.cfl", float, solver.cfl, "adaptive substep CFL number, (0, 1]"),
    PBF_SETTING("max_time_step", "solver.max_time_step", float, solver.maxTimeStep,
                "largest substep, seconds, (0, 1]"),
    PBF_SETTING("max_substeps", "solver.max_substeps", int, solver.maxSubsteps,
                "most substeps per frame, [1, 10000]"),
    PBF_SETTING("substeps", "solver.substeps", int, solver.fixedSubsteps,
                "substeps per frame in fixed mode, [1, 10000]"),
    PBF_SETTING("restitution", "solver.restitution", float, solver.restitution,
                "wall restitution, [0, 1]"),
    PBF_SETTING("friction", "solver.friction", float, solver.friction, "wall friction, [0, 1]"),
    PBF_SETTING("viscosity", "fluid.viscosity", float, fluid.viscosity, "XSPH c, [0, 1]"),
    PBF_SETTING("kinematic_viscosity", "fluid.kinematic_viscosity", float, fluid.kinematicViscosity,
                "nu, m^2/s, [0, 1]"),
    PBF_SETTING("vorticity", "fluid.vorticity", float, fluid.vorticity,
                "vorticity confinement epsilon, [0, 10]"),
    PBF_SETTING("rest_density", "fluid.rest_density", float, fluid.restDensity, "kg/m^3, (0, 1e5]"),
    PBF_SETTING("gravity", "gravity", Vec3, gravity, "m/s^2"),
    PBF_SETTING("kernel_radius_factor", "solver.kernel_radius_factor", float,
                solver.kernelRadiusFactor, "h / particle radius (fixed while the world runs)"),
    PBF_SETTING("particle_radius", "particle_radius", float, particleRadius,
                "metres (fixed while the world runs)"),
    PBF_SETTING("domain", "domain", Aabb, domain, "metres (fixed while the world runs)"),
};

#undef PBF_SETTING

// The field named by an attribute or a scene path; KeyError listing the names.
const Field& fieldNamed(std::string_view name) {
    for (const Field& f : kFields)
        if (name == f.attribute || name == f.path) return f;
    std::string names;
    for (const Field& f : kFields) names += std::string(names.empty() ? "" : ", ") + f.path;
    throw py::key_error("no live setting \"" + std::string(name) + "\"; the settings are " + names);
}

void apply(WorldHandle& handle, const Field& field, const py::handle& value) {
    handle.locked([&](World& world) {
        SimulationParams changed = world.settings();
        field.set(changed, value);
        world.applySettings(changed);
    });
}

py::object read(WorldHandle& handle, const Field& field) {
    return handle.locked([&](World& world) { return field.get(world.settings()); });
}

}  // namespace

void updateSettings(WorldHandle& handle, const py::dict& changes) {
    handle.locked([&](World& world) {
        SimulationParams changed = world.settings();
        for (const auto& [name, value] : changes)
            fieldNamed(name.cast<std::string>()).set(changed, value);
        world.applySettings(changed);
    });
}

void bindSettings(py::module_& m) {
    py::class_<Settings> settings(
        m, "Settings",
        "The live settings of a World (world.settings). Attributes read World::settings() and "
        "write through World::applySettings: a change is validated (pbf.SceneError naming the "
        "field, nothing changed) and takes effect at the next step. Items are addressed by "
        "scene-file paths too: settings[\"solver.iterations\"].");
    for (const Field& field : kFields) {
        settings.def_property(
            field.attribute, [&field](const Settings& s) { return read(s.world(), field); },
            [&field](const Settings& s, const py::handle& value) {
                apply(s.world(), field, value);
            },
            (std::string(field.doc) + " (" + field.path + ")").c_str());
    }
    settings
        .def(
            "__getitem__",
            [](const Settings& s, const std::string& name) {
                return read(s.world(), fieldNamed(name));
            },
            py::arg("path"))
        .def(
            "__setitem__",
            [](const Settings& s, const std::string& name, const py::handle& value) {
                apply(s.world(), fieldNamed(name), value);
            },
            py::arg("path"), py::arg("value"))
        .def(
            "update",
            [](const Settings& s, const py::handle& changes, const py::kwargs& more) {
                py::dict all;
                if (!changes.is_none()) all = py::dict(py::reinterpret_borrow<py::object>(changes));
                for (const auto& [k, v] : more) all[k] = v;
                updateSettings(s.world(), all);
            },
            py::arg("changes") = py::none(),
            "Applies several settings at once (all or nothing): update({\"solver.iterations\": "
            "6}, viscosity=0.02).")
        .def("keys",
             [](const Settings&) {
                 py::list paths;
                 for (const Field& f : kFields) paths.append(f.path);
                 return paths;
             })
        .def(
            "as_dict",
            [](const Settings& s) {
                return s.world().locked([](World& world) {
                    py::dict values;
                    for (const Field& f : kFields) values[f.path] = f.get(world.settings());
                    return values;
                });
            },
            "{scene path: value} of every setting.")
        .def(
            "params",
            [](const Settings& s) {
                return s.world().locked([](World& world) { return world.settings(); });
            },
            "A copy of the settings as SimulationParams (assign it back with world.settings = "
            "params).")
        .def("__repr__", [](const Settings& s) {
            return s.world().locked([](World& world) {
                std::string text = "Settings(";
                for (const Field& f : kFields)
                    text += std::string(f.attribute) + "=" +
                            py::repr(f.get(world.settings())).cast<std::string>() +
                            (&f == &kFields[std::size(kFields) - 1] ? ")" : ", ");
                return text;
            });
        });
}

}  // namespace pbf::python
