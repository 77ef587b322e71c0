#include "scene_file.hpp"

#include "errors.hpp"

namespace pbf::python {

namespace py = pybind11;

std::vector<SceneOverride> overridesFrom(const py::handle& overrides) {
    std::vector<SceneOverride> result;
    if (overrides.is_none()) return result;
    if (py::isinstance<py::dict>(overrides)) {
        const py::object dumps = py::module_::import("json").attr("dumps");
        for (const auto& [key, value] : py::reinterpret_borrow<py::dict>(overrides)) {
            if (!py::isinstance<py::str>(key))
                throw py::type_error(
                    "overrides: keys must be field paths such as "
                    "\"solver.iterations\", got " +
                    py::repr(key).cast<std::string>());
            const std::string text = py::isinstance<py::str>(value)
                                         ? value.cast<std::string>()
                                         : dumps(value).cast<std::string>();
            result.push_back({key.cast<std::string>(), text});
        }
        return result;
    }
    if (py::isinstance<py::str>(overrides))  // one "a=b" is a common slip for ["a=b"]
        return {parseOverride(overrides.cast<std::string>())};
    for (const py::handle item : py::iter(overrides)) {
        if (!py::isinstance<py::str>(item))
            throw py::type_error("overrides: expected \"FIELD=VALUE\" strings, got " +
                                 py::repr(item).cast<std::string>());
        result.push_back(parseOverride(item.cast<std::string>()));
    }
    return result;
}

std::string pathFrom(const py::handle& path) {
    return py::module_::import("os").attr("fspath")(path).cast<std::string>();
}

Scene loadSceneFrom(const py::handle& path, const py::handle& overrides) {
    const std::string file = pathFrom(path);
    const std::vector<SceneOverride> parsed = overridesFrom(overrides);
    return withSceneFile(file, [&] { return loadScene(file, parsed); });
}

}  // namespace pbf::python
