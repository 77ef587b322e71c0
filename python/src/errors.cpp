#include "errors.hpp"

#include "bindings.hpp"
#include "pbf/io/io.hpp"

namespace pbf::python {
namespace {

// pbf.StateError, created once at import. Deliberately leaked: a Python
// object destroyed by a C++ static destructor after the interpreter has
// finalised would crash at exit.
py::handle stateErrorType;

const char* kindName(StepError::Kind kind) {
    return kind == StepError::Kind::BadState ? "bad_state" : "failure";
}

}  // namespace

void raiseStepError(const StepError& error, py::object summary) {
    py::object exception = py::reinterpret_borrow<py::object>(stateErrorType)(error.message);
    exception.attr("kind") = kindName(error.kind);
    exception.attr("frame") = error.frame;
    exception.attr("substep") = error.substep;
    exception.attr("stage") = error.stage;
    exception.attr("particle_id") =
        error.particle ? py::object(py::int_(error.particle->id)) : py::object(py::none());
    exception.attr("problem") =
        error.particle ? py::object(py::str(error.particle->problem)) : py::object(py::none());
    exception.attr("summary") = std::move(summary);
    PyErr_SetObject(stateErrorType.ptr(), exception.ptr());
    throw py::error_already_set();
}

void bindErrors(py::module_& m) {
    py::register_exception<SceneError>(m, "SceneError", PyExc_ValueError).doc() =
        "An invalid scene, world definition, override or live setting; the message names the "
        "file (when there is one) and the field, e.g. \"solver.iterations: must be in [1, 100], "
        "got 0\".";
    py::register_exception<IoError>(m, "IoError", PyExc_OSError).doc() =
        "A file pbf could not read or write (output directory, checkpoint, mesh); the message "
        "names the file.";
    stateErrorType = PyErr_NewExceptionWithDoc(
        "pbf._pbf.StateError",
        "A frame could not be completed: the state guard found a NaN, an infinite value or a "
        "particle faster than the limit (guard.max_speed), or the step failed. Attributes: kind "
        "('bad_state' or 'failure'), frame, substep, stage, particle_id and problem (None when "
        "no particle is to blame), summary (pbf.run's RunSummary, else None).",
        PyExc_RuntimeError, nullptr);
    if (!stateErrorType) throw py::error_already_set();
    m.add_object("StateError", stateErrorType);
}

}  // namespace pbf::python
