// pbf.run: what `pbf run SCENE` does (apps/pbf/run_command.cpp), from Python:
// load the scene with overrides, set the output directory and frame count,
// runScene (PLY frames, stats.csv, summary.json, checkpoints). The GIL is
// released while it runs; Ctrl-C stops it between frames with a checkpoint
// written, as SIGINT does for the CLI, and is then raised as KeyboardInterrupt.
#include "pbf/run/run.hpp"

#include <optional>
#include <string>

#include "bindings.hpp"
#include "errors.hpp"
#include "pbf/core/threading.hpp"
#include "scene_file.hpp"

namespace pbf::python {
namespace {

// A RunSummary and where the run wrote.
struct RunResult : RunSummary {
    std::string scene;
    std::string directory;
};

// Sets the library's thread count for one run and puts the previous one back.
class ThreadCountScope {
  public:
    explicit ThreadCountScope(const py::handle& threads) {
        if (threads.is_none()) return;
        const int count = threads.cast<int>();
        if (count < 1 || count > 1024)
            throw py::value_error("threads: must be in [1, 1024], got " + std::to_string(count));
        previous_ = threadCount();
        setThreadCount(count);
    }
    ~ThreadCountScope() {
        if (previous_) setThreadCount(*previous_);
    }
    ThreadCountScope(const ThreadCountScope&) = delete;
    ThreadCountScope& operator=(const ThreadCountScope&) = delete;

  private:
    std::optional<int> previous_;
};

Scene sceneFrom(const py::handle& scene, const py::handle& overrides) {
    if (py::isinstance<Scene>(scene) || py::isinstance<WorldDef>(scene)) {
        if (!overrides.is_none())
            throw py::value_error(
                "overrides apply to scene files; change the definition's fields instead");
        if (py::isinstance<Scene>(scene)) return scene.cast<Scene>();
        Scene s;
        static_cast<WorldDef&>(s) = scene.cast<WorldDef>();
        s.output.directory = "out/" + s.name;
        return s;
    }
    return loadSceneFrom(scene, overrides);
}

void printToStderr(const std::string& text) {
    py::print(text, py::arg("file") = py::module_::import("sys").attr("stderr"),
              py::arg("flush") = true);
}

py::object run(const py::handle& sceneArgument, const py::handle& out, const py::handle& frames,
               const py::handle& overrides, const std::string& device, bool quiet,
               const py::handle& threads, bool resume, const py::handle& onFrame) {
    Scene scene = sceneFrom(sceneArgument, overrides);
    if (!out.is_none()) scene.output.directory = pathFrom(out);
    if (!frames.is_none()) {
        const int count = frames.cast<int>();
        if (count < 1 || count > 1000000)
            throw py::value_error("frames: must be in [1, 1000000], got " + std::to_string(count));
        scene.output.frames = count;
    }
    RunOptions options;
    options.world.backend = parseBackendKind(device);
    options.resume = resume;
    const ThreadCountScope threadScope(threads);

    // A KeyboardInterrupt, or an exception raised by on_frame: it stops the
    // run (checkpoint written) and is raised once runScene has returned.
    std::optional<py::error_already_set> pending;
    options.stopRequested = [&pending] {
        py::gil_scoped_acquire gil;
        if (!pending && PyErr_CheckSignals() != 0) pending.emplace();
        return pending.has_value();
    };
    const int total = scene.output.frames;
    if (!quiet || !onFrame.is_none())
        options.onFrame = [&](const FrameReport& r) {
            py::gil_scoped_acquire gil;
            if (pending) return;
            try {
                if (!quiet)
                    printToStderr("pbf.run: frame " + std::to_string(r.frame) + "/" +
                                  std::to_string(total) + " t=" + std::to_string(r.time) +
                                  " s substeps=" + std::to_string(r.substeps) +
                                  " step=" + std::to_string(r.stepMs) + " ms avg density error=" +
                                  std::to_string(100.0 * r.state.averageDensityError) + " %");
                if (!onFrame.is_none()) onFrame(r);
            } catch (py::error_already_set& e) {
                pending = std::move(e);
            }
        };
    if (!quiet)
        options.onNotice = [](const std::string& message) {
            py::gil_scoped_acquire gil;
            printToStderr("pbf.run: " + message);
        };

    RunResult result;
    result.scene = scene.name;
    result.directory = scene.output.directory;
    {
        py::gil_scoped_release release;
        static_cast<RunSummary&>(result) = runScene(scene, options);
    }
    if (pending) throw *pending;
    if (result.error) raiseStepError(*result.error, py::cast(result));
    return py::cast(result);
}

}  // namespace

void bindRun(py::module_& m) {
    py::class_<RunResult>(m, "RunSummary", "What pbf.run did (also in <directory>/summary.json).")
        .def_readonly("scene", &RunResult::scene)
        .def_readonly("directory", &RunResult::directory)
        .def_readonly("frames", &RunResult::frames, "frames completed")
        .def_readonly("particles", &RunResult::particles)
        .def_readonly("simulated_seconds", &RunResult::simulatedSeconds)
        .def_readonly("wall_seconds", &RunResult::wallSeconds)
        .def_readonly("substeps", &RunResult::substeps)
        .def_readonly("particle_steps_per_second", &RunResult::particleStepsPerSecond)
        .def_readonly("max_density_error", &RunResult::maxDensityError, "over all frames")
        .def_readonly("average_density_error", &RunResult::averageDensityError,
                      "mean over frames of the per-frame average")
        .def_readonly("max_escaped", &RunResult::maxEscaped, "0 in a correct run")
        .def_readonly("max_inside_solid", &RunResult::maxInsideSolid, "0 in a correct run")
        .def_readonly("skipped_in_solids", &RunResult::skippedInSolids)
        .def_readonly("emitted", &RunResult::emitted, "particles the emitters added")
        .def_readonly("removed", &RunResult::removed, "particles the outlets removed")
        .def_property_readonly("resumed_from_frame",
                               [](const RunResult& r) -> py::object {
                                   if (r.resumedFromFrame < 0) return py::none();
                                   return py::int_(r.resumedFromFrame);
                               })
        .def_readonly("interrupted", &RunResult::interrupted)
        .def_readonly("last_frame", &RunResult::lastFrame, "last frame written")
        .def_property_readonly("checkpoint",
                               [](const RunResult& r) -> py::object {
                                   if (r.checkpoint.empty()) return py::none();
                                   return py::str(r.checkpoint.string());
                               })
        .def_property_readonly("error",
                               [](const RunResult& r) -> py::object {
                                   if (!r.error) return py::none();
                                   return py::str(r.error->message);
                               })
        .def("as_dict",
             [](const py::object& self) {
                 py::dict d;
                 for (const char* field : {"scene",
                                           "directory",
                                           "frames",
                                           "particles",
                                           "simulated_seconds",
                                           "wall_seconds",
                                           "substeps",
                                           "particle_steps_per_second",
                                           "max_density_error",
                                           "average_density_error",
                                           "max_escaped",
                                           "max_inside_solid",
                                           "skipped_in_solids",
                                           "emitted",
                                           "removed",
                                           "resumed_from_frame",
                                           "interrupted",
                                           "last_frame",
                                           "checkpoint",
                                           "error"})
                     d[field] = self.attr(field);
                 return d;
             })
        .def("__repr__", [](const py::object& self) {
            return reprOf(self, "RunSummary",
                          {"scene", "directory", "frames", "particles", "wall_seconds",
                           "particle_steps_per_second", "average_density_error",
                           "max_density_error", "checkpoint", "error"});
        });

    m.def("run", &run, py::arg("scene"), py::arg("out") = py::none(),
          py::arg("frames") = py::none(), py::arg("overrides") = py::none(),
          py::arg("device") = "cpu", py::arg("quiet") = true, py::arg("threads") = py::none(),
          py::arg("resume") = false, py::arg("on_frame") = py::none(),
          "What `pbf run` does: simulates `scene` (a scene file path, or a Scene / WorldDef "
          "built in code) and writes PLY frames, stats.csv, summary.json and checkpoints to "
          "`out` (default: the scene's output.directory). Returns a RunSummary; raises "
          "pbf.StateError (with .summary) when a frame fails, pbf.SceneError / "
          "FileNotFoundError for a bad scene, pbf.IoError when an output cannot be written. "
          "on_frame(report) is called after every frame; quiet=False prints progress to "
          "stderr; threads sets the worker threads for this run; resume continues from the "
          "checkpoint in `out`.");
}

}  // namespace pbf::python
