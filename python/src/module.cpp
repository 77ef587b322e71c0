// The _pbf extension module; python/pbf/__init__.py re-exports it as `pbf`.
// One file per concept: params.cpp, definition.cpp (world definition and
// scene files), settings.cpp (live settings), world.cpp (pbf.World and its
// particle views), run.cpp (pbf.run), errors.cpp.
#include <string>

#include "bindings.hpp"
#include "pbf/core/threading.hpp"
#include "pbf/core/version.hpp"

PYBIND11_MODULE(_pbf, m) {
    namespace py = pybind11;
    using namespace pbf::python;
    m.doc() = "Position Based Fluids (Macklin & Mueller 2013) water simulation: the C++ library.";
    m.attr("__version__") = pbf::kVersion;

    bindErrors(m);
    bindParams(m);
    bindDefinition(m);
    bindSettings(m);
    bindWorld(m);
    bindRun(m);

    m.def(
        "set_threads",
        [](int count) {
            if (count < 1 || count > 1024)
                throw py::value_error("threads: must be in [1, 1024], got " +
                                      std::to_string(count));
            pbf::setThreadCount(count);
        },
        py::arg("count"),
        "Worker threads of every parallel pass (results are bit-identical for any count).");
    m.def("threads", &pbf::threadCount, "The worker thread count.");
    m.def("hardware_threads", &pbf::hardwareThreadCount);
}
