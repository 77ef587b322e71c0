// pbf.World: one simulation driven from Python (include/pbf/world/world.hpp).
//
//   world = pbf.World.from_scene("scenes/dam_break.json", {"solver.iterations": 8})
//   report = world.step_frame()        # GIL released while the solver works
//   x = world.positions                # (N, 3) float32 view, id order
//   world.settings.viscosity = 0.02    # validated, effective at the next step
#include <string>
#include <utility>
#include <vector>

#include "bindings.hpp"
#include "errors.hpp"
#include "particle_views.hpp"
#include "scene_file.hpp"
#include "settings.hpp"
#include "world_handle.hpp"

namespace pbf::python {
namespace {

using Handle = std::shared_ptr<WorldHandle>;

void bindReports(py::module_& m) {
    py::class_<StateStatistics>(m, "StateStatistics",
                                "Statistics of a particle state (the columns of stats.csv).")
        .def_readonly("particles", &StateStatistics::particles)
        .def_readonly("average_density_error", &StateStatistics::averageDensityError,
                      "mean of max(rho / rho0 - 1, 0)")
        .def_readonly("max_density_error", &StateStatistics::maxDensityError)
        .def_readonly("kinetic_energy", &StateStatistics::kineticEnergy, "J")
        .def_readonly("max_speed", &StateStatistics::maxSpeed, "m/s")
        .def_readonly("momentum", &StateStatistics::momentum, "kg m/s")
        .def_readonly("escaped", &StateStatistics::escaped, "particles outside the domain (0)")
        .def_readonly("inside_solid", &StateStatistics::insideSolid, "particles inside a solid (0)")
        .def("__repr__", [](const py::object& self) {
            return reprOf(self, "StateStatistics",
                          {"particles", "average_density_error", "max_density_error",
                           "kinetic_energy", "max_speed", "escaped", "inside_solid"});
        });

    py::class_<StageTimes>(m, "StageTimes", "Wall-clock milliseconds per solver stage.")
        .def_readonly("predict", &StageTimes::predict)
        .def_readonly("neighbor_search", &StageTimes::neighborSearch)
        .def_readonly("solve", &StageTimes::solve)
        .def_readonly("post_process", &StageTimes::postProcess)
        .def_readonly("total", &StageTimes::total)
        .def_readonly("grid_build", &StageTimes::gridBuild)
        .def_readonly("reorder", &StageTimes::reorder)
        .def_readonly("neighbor_lists", &StageTimes::neighborLists)
        .def_readonly("lambda_pass", &StageTimes::lambda)
        .def_readonly("delta_p", &StageTimes::deltaP)
        .def("__repr__", [](const py::object& self) {
            return reprOf(self, "StageTimes",
                          {"predict", "neighbor_search", "solve", "post_process", "total"});
        });

    py::class_<FrameReport>(m, "FrameReport", "What one frame did (World.step_frame).")
        .def_readonly("frame", &FrameReport::frame, "frames completed")
        .def_readonly("time", &FrameReport::time, "simulated seconds")
        .def_readonly("substeps", &FrameReport::substeps, "solver steps in this frame")
        .def_readonly("iterations", &FrameReport::iterations, "density iterations per substep")
        .def_readonly("emitted", &FrameReport::emitted, "particles the emitters added this frame")
        .def_readonly("removed", &FrameReport::removed, "particles the outlets removed this frame")
        .def_readonly("step_ms", &FrameReport::stepMs, "average wall-clock ms per substep")
        .def_readonly("stage_ms", &FrameReport::stageMs, "summed over the frame's substeps")
        .def_readonly("statistics", &FrameReport::state)
        .def(
            "as_dict",
            [](const FrameReport& r) {
                py::dict d;
                d["frame"] = r.frame;
                d["time"] = r.time;
                d["substeps"] = r.substeps;
                d["iterations"] = r.iterations;
                d["emitted"] = r.emitted;
                d["removed"] = r.removed;
                d["step_ms"] = r.stepMs;
                d["particles"] = r.state.particles;
                d["average_density_error"] = r.state.averageDensityError;
                d["max_density_error"] = r.state.maxDensityError;
                d["kinetic_energy"] = r.state.kineticEnergy;
                d["max_speed"] = r.state.maxSpeed;
                d["escaped"] = r.state.escaped;
                d["inside_solid"] = r.state.insideSolid;
                return d;
            },
            "The report flattened (one row of a table).")
        .def("__repr__", [](const py::object& self) {
            return reprOf(self, "FrameReport",
                          {"frame", "time", "substeps", "iterations", "step_ms", "statistics"});
        });
}

Handle makeWorld(const WorldDef& definition, const std::string& device) {
    WorldOptions options;
    options.backend = parseBackendKind(device);  // std::invalid_argument -> ValueError
    // Building solids from meshes takes a while: let other threads run.
    py::gil_scoped_release release;
    return std::make_shared<WorldHandle>(World(definition, options));
}

FrameReport stepFrame(WorldHandle& handle) {
    FrameResult result = handle.unlocked([](World& world) { return world.stepFrame(); });
    if (!result.ok()) raiseStepError(*result.error);
    return result.report;
}

std::vector<Vec3> pointsFrom(const py::handle& values, const char* what) {
    const auto array =
        py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(values);
    if (!array || !(array.ndim() == 2 && array.shape(1) == 3))
        throw py::value_error(std::string("add_particles: ") + what +
                              " must be an (N, 3) array of numbers");
    std::vector<Vec3> points(static_cast<std::size_t>(array.shape(0)));
    const auto a = array.unchecked<2>();
    for (py::ssize_t i = 0; i < array.shape(0); ++i)
        points[static_cast<std::size_t>(i)] = {a(i, 0), a(i, 1), a(i, 2)};
    return points;
}

}  // namespace

void bindBodies(py::module_& m, py::class_<WorldHandle, Handle>& world);  // bodies.cpp

namespace {

void bindWorldClass(py::module_& m) {
    py::class_<WorldHandle, Handle> world(
        m, "World",
        "One simulation: its definition, live settings (world.settings) and particles "
        "(numpy views in id order). step_frame() advances one output frame (1 / fps seconds) "
        "with the GIL released.");
    world
        .def(py::init(&makeWorld), py::arg("definition"), py::arg("device") = "cpu",
             "A world from a WorldDef (or Scene); device \"cpu\" (SIMD, default), "
             "\"reference\" (scalar oracle, slow), \"cuda\" (NVIDIA GPU) or \"cuda-on-cpu\" "
             "(the GPU backend's code on the CPU). Raises pbf.SceneError for an invalid "
             "definition or one too large for the device, ValueError for an unknown device, "
             "RuntimeError naming the device when it cannot run here.")
        .def_static(
            "from_scene",
            [](const py::handle& path, const py::handle& overrides, const std::string& device) {
                return makeWorld(loadSceneFrom(path, overrides), device);
            },
            py::arg("path"), py::arg("overrides") = py::none(), py::arg("device") = "cpu",
            "A world from a scene file, with overrides as pbf run --set takes them: "
            "{\"solver.iterations\": 8} or [\"solver.iterations=8\"].")
        .def("step_frame", &stepFrame,
             "Simulates one frame; returns its FrameReport. Raises pbf.StateError (the frame, "
             "substep and particle id in the message) when the state guard fires; the world is "
             "then left as the failing substep made it.")
        .def(
            "step_frames",
            [](WorldHandle& handle, int count) {
                std::vector<FrameReport> reports;
                for (int k = 0; k < count; ++k) {
                    reports.push_back(stepFrame(handle));
                    // Ctrl-C between frames.
                    if (PyErr_CheckSignals() != 0) throw py::error_already_set();
                }
                return reports;
            },
            py::arg("count"), "Simulates `count` frames; returns their reports.")
        .def(
            "report", [](WorldHandle& h) { return h.locked([](World& w) { return w.report(); }); },
            "Statistics of the current state.")
        .def_property_readonly(
            "frame", [](WorldHandle& h) { return h.locked([](World& w) { return w.frame(); }); })
        .def_property_readonly(
            "time", [](WorldHandle& h) { return h.locked([](World& w) { return w.time(); }); },
            "simulated seconds")
        .def_property_readonly(
            "frame_duration",
            [](WorldHandle& h) { return h.locked([](World& w) { return w.frameDuration(); }); },
            "1 / fps seconds")
        .def_property_readonly(
            "particle_count",
            [](WorldHandle& h) { return h.locked([](World& w) { return w.particleCount(); }); })
        .def_property_readonly(
            "skipped_particles",
            [](WorldHandle& h) { return h.locked([](World& w) { return w.skippedParticles(); }); },
            "fluid-block sites left empty because a solid was there")
        .def_property_readonly(
            "emitted_particles",
            [](WorldHandle& h) { return h.locked([](World& w) { return w.emittedParticles(); }); },
            "particles the emitters added so far")
        .def_property_readonly(
            "removed_particles",
            [](WorldHandle& h) { return h.locked([](World& w) { return w.removedParticles(); }); },
            "particles the outlets removed so far")
        .def_property_readonly("device",
                               [](WorldHandle& h) {
                                   return h.locked([](World& w) {
                                       return std::string(backendName(w.backend().kind()));
                                   });
                               })
        .def_property_readonly(
            "definition",
            [](WorldHandle& h) { return h.locked([](World& w) { return w.definition(); }); },
            "A copy of the definition the world was built from.")
        .def_property(
            "speed_limit",
            [](WorldHandle& h) { return h.locked([](World& w) { return w.speedLimit(); }); },
            [](WorldHandle& h, double limit) {
                h.locked([limit](World& w) { w.setSpeedLimit(limit); });
            },
            "m/s above which the state guard fails a frame (<= 0: no speed check)")
        .def_property(
            "settings", [](const Handle& h) { return Settings(h); },
            [](WorldHandle& h, const py::handle& value) {
                if (py::isinstance<py::dict>(value)) {
                    updateSettings(h, py::reinterpret_borrow<py::dict>(value));
                    return;
                }
                const auto params = value.cast<SimulationParams>();
                h.locked([&params](World& w) { w.applySettings(params); });
            },
            "The live settings (pbf.Settings); assign a SimulationParams or a dict to change "
            "several at once.")
        .def_property_readonly(
            "positions",
            [](WorldHandle& h) {
                return h.locked([](World& w) { return positionsView(w.arraysById()); });
            },
            "(N, 3) float32 view in id order, metres; writes take effect at the next step")
        .def_property_readonly(
            "velocities",
            [](WorldHandle& h) {
                return h.locked([](World& w) { return velocitiesView(w.arraysById()); });
            },
            "(N, 3) float32 view in id order, m/s; writes take effect at the next step")
        .def_property_readonly(
            "densities",
            [](WorldHandle& h) {
                return h.locked([](World& w) { return densitiesView(w.arraysById()); });
            },
            "(N,) float32 read-only view in id order, kg/m^3")
        .def_property_readonly(
            "ids",
            [](WorldHandle& h) {
                return h.locked([](World& w) { return idsView(w.arraysById()); });
            },
            "(N,) uint64 read-only view: ids[k] == k")
        .def(
            "add_particles",
            [](WorldHandle& h, const py::handle& positions, const py::handle& velocities) {
                const std::vector<Vec3> x = pointsFrom(positions, "positions");
                const std::vector<Vec3> v = velocities.is_none()
                                                ? std::vector<Vec3>(x.size())
                                                : pointsFrom(velocities, "velocities");
                h.locked([&](World& w) { w.addParticles(x, v); });
            },
            py::arg("positions"), py::arg("velocities") = py::none(),
            "Adds particles ((N, 3) arrays; velocities default to 0) with the next free ids. "
            "Views taken before no longer follow the world: read world.positions again.")
        .def_property_readonly(
            "solids",
            [](WorldHandle& h) {
                return h.locked([](World& w) {
                    std::vector<std::string> names;
                    const SolidSet& s = w.solids();
                    for (std::size_t k = 0; k < s.size(); ++k)
                        names.push_back(s.shape(k).describe());
                    return names;
                });
            },
            "A description of each solid.")
        .def(
            "set_solid_motion",
            [](WorldHandle& h, std::size_t index, const Vec3& position, const Vec3& rotation,
               const Vec3& velocity, const Vec3& angularVelocity) {
                const SolidMotion motion{
                    {position, fromEulerDegrees(rotation)}, velocity, angularVelocity};
                h.locked([&](World& w) { w.setSolidMotion(index, motion); });
            },
            py::arg("index"), py::arg("position") = Vec3{}, py::arg("rotation") = Vec3{},
            py::arg("velocity") = Vec3{}, py::arg("angular_velocity") = Vec3{},
            "Moves solid `index` between frames: its pose (translation, Euler degrees about x, "
            "y, z; analytic solids are defined in world coordinates, so this is their "
            "displacement) and the velocity (m/s) and angular velocity (rad/s) the fluid feels "
            "at contacts.")
        .def("__repr__", [](WorldHandle& h) {
            return h.locked([](World& w) {
                return "World(name=" + py::repr(py::str(w.definition().name)).cast<std::string>() +
                       ", particles=" + std::to_string(w.particleCount()) +
                       ", frame=" + std::to_string(w.frame()) +
                       ", time=" + py::repr(py::float_(w.time())).cast<std::string>() +
                       ", device=" + std::string(backendName(w.backend().kind())) + ")";
            });
        });
    bindBodies(m, world);
}

}  // namespace

void bindWorld(py::module_& m) {
    bindReports(m);
    bindWorldClass(m);
}

}  // namespace pbf::python
