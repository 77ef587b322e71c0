// Loading scene files from Python: a path (str or os.PathLike) and
// overrides given the way Python users write them.
#pragma once

#include <pybind11/pybind11.h>

#include <string>
#include <vector>

#include "pbf/io/scene.hpp"

namespace pbf::python {

// Overrides as `pbf run --set` takes them, from
//   None                                   no overrides
//   {"solver.iterations": 8, "gravity": [0, -3, 0], "solver.time_step": "fixed"}
//                                          values: a str is passed as written (JSON or
//                                          a bare string), anything else as json.dumps(value)
//   ["solver.iterations=8", ...]           the CLI's FIELD=VALUE strings
// Throws SceneError for a malformed "FIELD=VALUE" and TypeError otherwise.
std::vector<SceneOverride> overridesFrom(const pybind11::handle& overrides);

// os.fspath(path) as a std::string.
std::string pathFrom(const pybind11::handle& path);

// loadScene with the overrides above; a missing file raises
// FileNotFoundError, an invalid one pbf.SceneError (the CLI's messages).
Scene loadSceneFrom(const pybind11::handle& path, const pybind11::handle& overrides);

}  // namespace pbf::python
