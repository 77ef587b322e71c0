// Python exceptions of the pbf module. C++ errors keep their messages, which
// name the file and the field (or the frame, substep and particle):
//   pbf::SceneError -> pbf.SceneError (a ValueError)
//   pbf::IoError    -> pbf.IoError (an OSError)
//   a failed frame  -> pbf.StateError (a RuntimeError) with the StepError's
//                      fields as attributes
#pragma once

#include <pybind11/pybind11.h>

#include <cerrno>
#include <filesystem>

#include "pbf/world/world.hpp"

namespace pbf::python {

// Raises pbf.StateError for `error` (GIL held). `summary` becomes the
// exception's `summary` attribute (pbf.run passes its RunSummary).
[[noreturn]] void raiseStepError(const StepError& error,
                                 pybind11::object summary = pybind11::none());

// Calls `load` (which reads the scene file `path`); a missing file is raised
// as FileNotFoundError (errno ENOENT) carrying the C++ message, which names
// the file (`filename` stays None: setting it would make str(error) print
// "[Errno None] None: 'x.json'" instead of the message),
// every other problem as pbf.SceneError / pbf.IoError.
template <class Load>
auto withSceneFile(const std::filesystem::path& path, Load&& load) {
    try {
        return load();
    } catch (const SceneError& e) {
        std::error_code ec;
        if (std::filesystem::exists(path, ec) || ec) throw;
        auto error =
            pybind11::reinterpret_borrow<pybind11::object>(PyExc_FileNotFoundError)(e.what());
        error.attr("errno") = ENOENT;
        PyErr_SetObject(PyExc_FileNotFoundError, error.ptr());
        throw pybind11::error_already_set();
    }
}

}  // namespace pbf::python
