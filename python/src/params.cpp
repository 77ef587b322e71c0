// Simulation parameters (include/pbf/params.hpp) and the box type: the
// plain structs a definition is made of. Field names are those of scene
// files (docs/scenes.md), so `params.solver.iterations` in Python is
// "solver.iterations" in a scene and in error messages.
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

void bindFluid(py::module_& m) {
    py::class_<FluidParams>(m, "FluidParams", "Fluid material (docs/scenes.md, \"fluid\").")
        .def(py::init<>())
        .def_property("rest_density", floatGetter(&FluidParams::restDensity),
                      floatSetter(&FluidParams::restDensity), "kg/m^3, (0, 1e5]")
        .def_property("viscosity", floatGetter(&FluidParams::viscosity),
                      floatSetter(&FluidParams::viscosity),
                      "XSPH c, [0, 1] (a smoothing, not a viscosity in m^2/s)")
        .def_property("kinematic_viscosity", floatGetter(&FluidParams::kinematicViscosity),
                      floatSetter(&FluidParams::kinematicViscosity), "nu, m^2/s, [0, 1]")
        .def_property("vorticity", floatGetter(&FluidParams::vorticity),
                      floatSetter(&FluidParams::vorticity), "confinement epsilon, [0, 10]")
        .def("__repr__", [](const py::object& self) {
            return reprOf(self, "FluidParams",
                          {"rest_density", "viscosity", "kinematic_viscosity", "vorticity"});
        });
}

void bindSolver(py::module_& m) {
    py::class_<ArtificialPressureParams>(
        m, "ArtificialPressureParams",
        "s_corr = -k (W(r) / W(dq h))^n (paper eq. 13-14), k in units of the constraint's scale.")
        .def(py::init<>())
        .def_property("k", floatGetter(&ArtificialPressureParams::k),
                      floatSetter(&ArtificialPressureParams::k), "[0, 1]")
        .def_readwrite("n", &ArtificialPressureParams::n, "[1, 8]")
        .def_property("dq", floatGetter(&ArtificialPressureParams::dq),
                      floatSetter(&ArtificialPressureParams::dq), "fraction of h, (0, 1)")
        .def("__repr__", [](const py::object& self) {
            return reprOf(self, "ArtificialPressureParams", {"k", "n", "dq"});
        });

    py::class_<SolverParams>(m, "SolverParams", "Solver settings (docs/scenes.md, \"solver\").")
        .def(py::init<>())
        .def_readwrite("iterations", &SolverParams::iterations, "density iterations, [1, 100]")
        .def_property("max_density_error", floatGetter(&SolverParams::maxDensityError),
                      floatSetter(&SolverParams::maxDensityError),
                      "iterate to this average compression (relative), [0, 0.1]; 0: fixed "
                      "iterations")
        .def_readwrite("min_iterations", &SolverParams::minIterations,
                       "with max_density_error, [0, max_iterations]")
        .def_readwrite("max_iterations", &SolverParams::maxIterations,
                       "with max_density_error, [1, 1000]")
        .def_property("over_relaxation", floatGetter(&SolverParams::overRelaxation),
                      floatSetter(&SolverParams::overRelaxation),
                      "Jacobi omega, [0.5, 1.5]; -1 (default): automatic, 1.2 with "
                      "max_density_error > 0, else 1")
        .def_property("warm_start", floatGetter(&SolverParams::warmStart),
                      floatSetter(&SolverParams::warmStart),
                      "fraction of the last pressure acceleration, [0, 1]")
        .def_property("relaxation", floatGetter(&SolverParams::relaxation),
                      floatSetter(&SolverParams::relaxation), "CFM epsilon, [1e-6, 10]")
        .def_readwrite("artificial_pressure", &SolverParams::artificialPressure)
        .def_property("kernel_radius_factor", floatGetter(&SolverParams::kernelRadiusFactor),
                      floatSetter(&SolverParams::kernelRadiusFactor), "h / particle radius, [3, 6]")
        .def_property(
            "time_step", [](const SolverParams& s) { return timeStepName(s.timeStepMode); },
            [](SolverParams& s, const std::string& name) {
                s.timeStepMode = parseTimeStep(name, "solver.time_step");
            },
            "\"adaptive\" (CFL-limited substeps) or \"fixed\" (`substeps` per frame)")
        .def_property("cfl", floatGetter(&SolverParams::cfl), floatSetter(&SolverParams::cfl),
                      "(0, 1]")
        .def_property("max_time_step", floatGetter(&SolverParams::maxTimeStep),
                      floatSetter(&SolverParams::maxTimeStep), "seconds, (0, 1]")
        .def_readwrite("max_substeps", &SolverParams::maxSubsteps, "per frame, [1, 10000]")
        .def_readwrite("substeps", &SolverParams::fixedSubsteps,
                       "fixed mode: substeps per frame, [1, 10000]")
        .def_property("restitution", floatGetter(&SolverParams::restitution),
                      floatSetter(&SolverParams::restitution), "[0, 1]")
        .def_property("friction", floatGetter(&SolverParams::friction),
                      floatSetter(&SolverParams::friction), "[0, 1]")
        .def("__repr__", [](const py::object& self) {
            return reprOf(self, "SolverParams",
                          {"iterations", "relaxation", "artificial_pressure",
                           "kernel_radius_factor", "time_step", "cfl", "max_time_step",
                           "max_substeps", "substeps", "restitution", "friction"});
        });
}

void bindSimulation(py::module_& m) {
    py::class_<SimulationParams>(m, "SimulationParams",
                                 "Domain, gravity, particle radius, fluid and solver parameters.")
        .def(py::init<>())
        .def_readwrite("domain", &SimulationParams::domain, "metres; particles never leave it")
        .def_readwrite("gravity", &SimulationParams::gravity, "m/s^2")
        .def_property("particle_radius", floatGetter(&SimulationParams::particleRadius),
                      floatSetter(&SimulationParams::particleRadius),
                      "metres; the initial lattice spacing is 2 r")
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
            "\"\" when valid, else \"field: problem\" for the first invalid field.")
        .def("__repr__", [](const py::object& self) {
            return reprOf(self, "SimulationParams",
                          {"domain", "gravity", "particle_radius", "fluid", "solver"});
        });
}

}  // namespace

const char* timeStepName(TimeStepMode mode) {
    return mode == TimeStepMode::Fixed ? "fixed" : "adaptive";
}

TimeStepMode parseTimeStep(const std::string& name, const std::string& field) {
    if (name == "adaptive") return TimeStepMode::Adaptive;
    if (name == "fixed") return TimeStepMode::Fixed;
    throw SceneError(field + ": expected \"adaptive\" or \"fixed\", got \"" + name + "\"");
}

std::string reprOf(py::handle self, const char* type, std::initializer_list<const char*> fields) {
    std::string text = std::string(type) + "(";
    const char* separator = "";
    for (const char* field : fields) {
        text +=
            separator + std::string(field) + "=" + py::repr(self.attr(field)).cast<std::string>();
        separator = ", ";
    }
    return text + ")";
}

void bindParams(py::module_& m) {
    bindAabb(m);
    bindFluid(m);
    bindSolver(m);
    bindSimulation(m);
}

}  // namespace pbf::python
