#include "settings.hpp"

#include <string>
#include <string_view>

#include "bindings.hpp"

namespace pbf::python {
namespace {

// The row named by an attribute or a scene path; KeyError listing the paths.
const ParamInfo& paramNamed(std::string_view name) {
    if (const ParamInfo* p = findParam(name)) return *p;
    std::string names;
    for (const ParamInfo& p : paramTable())
        names += std::string(names.empty() ? "" : ", ") + std::string(p.path);
    throw py::key_error("no setting \"" + std::string(name) + "\"; the settings are " + names);
}

void apply(WorldHandle& handle, const ParamInfo& param, const py::handle& value) {
    const ParamValue converted = paramFromPython(param, value);
    handle.locked([&](World& world) {
        SimulationParams changed = world.settings();
        param.set(changed, converted);
        world.applySettings(changed);
    });
}

py::object read(WorldHandle& handle, const ParamInfo& param) {
    const ParamValue value =
        handle.locked([&](World& world) { return param.get(world.settings()); });
    return paramToPython(value);
}

}  // namespace

void updateSettings(WorldHandle& handle, const py::dict& changes) {
    std::vector<std::pair<const ParamInfo*, ParamValue>> converted;
    for (const auto& [name, value] : changes) {
        const ParamInfo& param = paramNamed(name.cast<std::string>());
        converted.emplace_back(&param, paramFromPython(param, value));
    }
    handle.locked([&](World& world) {
        SimulationParams changed = world.settings();
        for (const auto& [param, value] : converted) param->set(changed, value);
        world.applySettings(changed);
    });
}

void bindSettings(py::module_& m) {
    py::class_<Settings> settings(
        m, "Settings",
        "The settings of a World (world.settings): every row of the parameter table "
        "(docs/scenes.md, `pbf params`). Attributes read World::settings() and write through "
        "World::applySettings: a change is validated (pbf.SceneError naming the field, nothing "
        "changed) and takes effect at the next step; the domain, particle radius and kernel "
        "radius factor are fixed while the world runs (writing them raises). Items are "
        "addressed by scene-file paths too: settings[\"solver.iterations\"].");
    for (const ParamInfo& p : paramTable()) {
        const ParamInfo* param = &p;
        settings.def_property(
            std::string(p.attribute).c_str(),
            [param](const Settings& s) { return read(s.world(), *param); },
            [param](const Settings& s, const py::handle& value) {
                apply(s.world(), *param, value);
            },
            (std::string(p.description) + " (" + std::string(p.path) +
             (p.live ? ")" : "; fixed while the world runs)"))
                .c_str());
    }
    settings
        .def(
            "__getitem__",
            [](const Settings& s, const std::string& name) {
                return read(s.world(), paramNamed(name));
            },
            py::arg("path"))
        .def(
            "__setitem__",
            [](const Settings& s, const std::string& name, const py::handle& value) {
                apply(s.world(), paramNamed(name), value);
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
                 for (const ParamInfo& p : paramTable()) paths.append(std::string(p.path));
                 return paths;
             })
        .def(
            "as_dict",
            [](const Settings& s) {
                const SimulationParams params =
                    s.world().locked([](World& world) { return world.settings(); });
                py::dict values;
                for (const ParamInfo& p : paramTable())
                    values[py::str(std::string(p.path))] = paramToPython(p.get(params));
                return values;
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
            const SimulationParams params =
                s.world().locked([](World& world) { return world.settings(); });
            std::string text = "Settings(";
            const char* separator = "";
            for (const ParamInfo& p : paramTable()) {
                text += separator + std::string(p.attribute) + "=" +
                        py::repr(paramToPython(p.get(params))).cast<std::string>();
                separator = ", ";
            }
            return text + ")";
        });
}

}  // namespace pbf::python
