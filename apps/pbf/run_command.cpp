// `pbf run SCENE`: simulate a scene, writing PLY frames, stats.csv and summary.json.
#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "commands.hpp"
#include "console.hpp"
#include "device_option.hpp"
#include "export_command.hpp"
#include "mesh_job.hpp"
#include "pbf/core/distributed.hpp"
#include "pbf/core/threading.hpp"
#include "pbf/io/checkpoint.hpp"
#include "pbf/io/h5part.hpp"
#include "pbf/io/io.hpp"
#include "pbf/io/scene.hpp"
#include "pbf/run/run.hpp"
#include "pbf/surface/vdb_points.hpp"
#include "run_images.hpp"
#include "stop_signals.hpp"

namespace pbf::cli {
namespace {

struct RunArguments {
    std::string scene;
    std::string out;
    int frames = 0;
    int threads = 0;
    std::vector<std::string> overrides;
    bool noParticles = false;
    bool quiet = false;
    bool vdbPoints = false;
    bool vtk = false;
    bool h5part = false;
    bool mesh = false;
    bool usd = false;
    bool resume = false;
    std::optional<std::string> render;  // --render [spheres|liquid|none]
    bool noPlot = false;
    std::string device = "cpu";
    int checkpointEvery = -1;         // -1: the scene's output.checkpoint_every
    double checkpointSeconds = -1.0;  // -1: the scene's output.checkpoint_seconds
};

// The command that continues a run (printed when a run stops early).
std::string resumeCommand(const RunArguments& args, const Scene& scene) {
    std::string command = "pbf run " + args.scene;
    for (const std::string& o : args.overrides) command += " --set '" + o + "'";
    command += " --out " + scene.output.directory;
    if (args.frames > 0) command += " --frames " + std::to_string(args.frames);
    return command + " --resume";
}

// Video, poster and the statistics plot at the end of a run; returns what was
// made for the summary line. Missing helpers (ffmpeg, matplotlib) are warned
// about and leave the exit status alone.
std::string finishPictures(const Scene& scene, RunImages* images, bool plot,
                           const std::function<void(const std::string&)>& warn) {
    const std::filesystem::path dir = scene.output.directory;
    std::string made;
    try {
        const StatsTable stats = readStatsCsv(dir / "stats.csv");
        if (images) made = images->finish(stats);
        if (plot) {
            const plot::Result r = plotRunStatistics(dir, dir / "stats.png");
            if (r.drawn)
                made += (made.empty() ? "" : ", ") + std::string("plot ") +
                        (dir / "stats.png").string();
            else
                warn("no plot: " + r.message);
        }
    } catch (const IoError& e) {
        warn(std::string("no pictures: ") + e.what());
    }
    return made;
}

int runScene(RunArguments args) {
    // Distributed: every rank simulates its slab; rank 0 writes the files
    // and speaks (the others are quiet and make no pictures).
    const bool writer = distributed::rank() == 0;
    if (!writer) {
        args.quiet = true;
        args.noPlot = true;
        args.render = "none";
        args.mesh = false;
    }
    std::vector<SceneOverride> overrides;
    for (const std::string& o : args.overrides) overrides.push_back(parseOverride(o));
    Scene scene = loadScene(args.scene, overrides);
    if (args.frames > 0) scene.output.frames = args.frames;
    if (!args.out.empty()) scene.output.directory = args.out;
    if (args.noParticles) scene.output.writeParticles = false;
    if (args.vdbPoints) scene.output.writeVdbPoints = true;
    if (args.vtk) scene.output.writeVtk = true;
    if (args.h5part) {
        if (!h5partBuilt())
            throw SceneError(
                "--h5part: this pbf was built without parallel HDF5 (PBF_HDF5=OFF); "
                "install libhdf5-openmpi-dev and reconfigure");
        scene.output.writeH5Part = true;
    }
    if (args.usd) scene.output.writeUsd = true;
    if (args.mesh && !scene.output.writeParticles)
        throw SceneError(
            "--mesh needs the PLY particle frames: drop --no-particles / output.particles=false");
    if (scene.output.writeUsd && !scene.output.writeParticles)
        throw SceneError(
            "--usd (output.usd) needs the PLY particle frames: drop --no-particles / "
            "output.particles=false");
    if (args.checkpointEvery >= 0) scene.output.checkpointEvery = args.checkpointEvery;
    if (args.checkpointSeconds >= 0.0)
        scene.output.checkpointSeconds = static_cast<float>(args.checkpointSeconds);
    if (args.render) scene.output.render.style = *args.render == "none" ? "" : *args.render;
    if (args.threads > 0) setThreadCount(args.threads);

    const std::size_t particles = countParticles(scene);
    if (!args.quiet)
        fmt::print(stderr,
                   "pbf run: {} (up to {} particles, {} frames at {} fps, {} threads) -> {}\n",
                   scene.name, particles, scene.output.frames, scene.fps, threadCount(),
                   scene.output.directory);
    ProgressBar progress("simulating", scene.output.frames, !args.quiet);
    RunOptions options;
    options.world.backend = selectDevice(args.device);
    if (distributed::size() > 1) {
        if (options.world.backend != BackendKind::Cpu)
            throw SceneError("--device " + args.device +
                             ": distributed runs (mpirun -np N, N > 1) use the cpu solver");
        options.world.backend = BackendKind::Mpi;
        if (!args.quiet)
            fmt::print(stderr, "pbf run: {} MPI ranks, {} threads each\n", distributed::size(),
                       threadCount());
    }
    options.onStart = [&](const World& world) {
        if (args.quiet) return;
        const LocalFrame& frame = world.localFrame();
        if (frame.shifted())
            fmt::print(stderr,
                       "pbf run: the domain is far from the origin: the solver keeps positions "
                       "relative to ({}, {}, {}) m (the solids below are in that frame)\n",
                       frame.origin.x, frame.origin.y, frame.origin.z);
        const SolidSet& solids = world.solids();
        for (std::size_t k = 0; k < solids.size(); ++k)
            fmt::print(stderr, "pbf run: solid {}: {}\n", k, solids.shape(k).describe());
        for (const SolidDescription& solid : world.definition().solids)
            if (const std::string waves = describe(solid.motion); !waves.empty())
                fmt::print(stderr, "pbf run: {}: {}\n", solid.field, waves);
        if (world.skippedParticles() > 0)
            fmt::print(
                stderr,
                "pbf run: {} fluid-block particles not created: they would be inside a solid\n",
                world.skippedParticles());
        if (const SolverParams& s = world.settings().solver;
            s.timeStepMode == TimeStepMode::Adaptive && world.depthStep() < s.maxTimeStep)
            fmt::print(stderr,
                       "pbf run: deep water: substeps of at most {:.3g} ms, not {:.3g} "
                       "(solver.depth_limit {:g}: a longer step lets the column slam and erupt as "
                       "it starts; docs/scenes.md, \"Deep water\")\n",
                       1e3 * world.depthStep(), 1e3 * s.maxTimeStep, s.depthLimit);
        const double particleVolume = std::pow(world.settings().particleSpacing(), 3.0);
        for (const Emitter& e : world.emitters())
            fmt::print(stderr,
                       "pbf run: emitter: {} particles per disc, {:.0f} particles/s ({:.3g} L/s "
                       "at {:.3g} m/s)\n",
                       e.discSize(), e.rate(), 1e3 * e.rate() * particleVolume,
                       length(e.velocity()));
        for (const OutletDescription& o : world.definition().outlets) {
            const OutletRegion& r = o.region;
            if (r.kind == OutletRegion::Kind::Box)
                fmt::print(stderr, "pbf run: {}: water leaves inside [{}, {}, {}] - [{}, {}, {}]\n",
                           o.field, r.box.min.x, r.box.min.y, r.box.min.z, r.box.max.x, r.box.max.y,
                           r.box.max.z);
            else
                fmt::print(stderr,
                           "pbf run: {}: water leaves past the plane through ({}, {}, {}) toward "
                           "({:.3g}, {:.3g}, {:.3g})\n",
                           o.field, r.point.x, r.point.y, r.point.z, r.normal.x, r.normal.y,
                           r.normal.z);
        }
    };
    // Warnings about optional outputs (images, video, plot): said once each,
    // never fatal; the simulation's files are the product.
    const auto warn = [](const std::string& message) {
        fmt::print(stderr, "pbf: warning: {}\n", message);
    };
    const std::unique_ptr<RunImages> images =
        writer ? RunImages::start(scene, warn) : std::unique_ptr<RunImages>();
    if (writer && (scene.output.writeVdbPoints || images))
        options.writeFrame = [&](int frame, const World& world) {
            if (scene.output.writeVdbPoints)
                surface::writeParticlesVdb(std::filesystem::path(scene.output.directory) /
                                               fmt::format("frame_{:05d}.vdb", frame),
                                           world.particles());
            if (images) images->write(frame, world);
        };
    options.onFrame = [&](const FrameReport& r) {
        progress.update(r.frame,
                        fmt::format("t={:.3f}s substeps={} step={:.1f}ms err={:.2f}%", r.time,
                                    r.substeps, r.stepMs, 100.0 * r.state.averageDensityError));
    };
    options.resume = args.resume;
    options.stopRequested = [] { return stopSignal() != 0; };
    options.onNotice = [&](const std::string& message) {
        if (!args.quiet) fmt::print(stderr, "pbf run: {}\n", message);
    };
    installStopHandlers();
    RunSummary s;
    try {
        s = pbf::runScene(scene, options);
    } catch (const IoError& e) {
        progress.finish();
        printError(e.what());
        return 1;
    }
    progress.finish();
    if (!writer)  // rank 0 reports; the status is the same on every rank
        return s.error                                    ? 4
               : s.interrupted                            ? 128 + stopSignal()
               : s.maxInsideSolid > 0 || s.maxEscaped > 0 ? 3
                                                          : 0;
    // Pictures and plots of what was simulated, also of a run the state
    // guard stopped (they show how it went bad); not of an interrupted run,
    // which is continued with --resume and finished then.
    std::string pictures;
    if (!s.interrupted) pictures = finishPictures(scene, images.get(), !args.noPlot, warn);
    if (s.error) {
        printError(s.error->message);
        return 4;
    }
    if (s.interrupted) {
        const int signal = stopSignal();
        fmt::print(stderr,
                   "pbf run: stopped by signal {} after frame {}; checkpoint written to {}\n"
                   "pbf run: continue with: {}\n",
                   signal, s.lastFrame, s.checkpoint.string(), resumeCommand(args, scene));
        return 128 + signal;
    }
    fmt::print(
        "pbf run: {} frames, {} particles, {:.3f} s simulated in {:.1f} s wall, {} substeps, "
        "{:.2f} M particle-steps/s, avg density error {:.2f} %, max {:.2f} %, escaped {} -> {}{}\n",
        s.frames, s.particles, s.simulatedSeconds, s.wallSeconds, s.substeps,
        s.particleStepsPerSecond * 1e-6, 100.0 * s.averageDensityError, 100.0 * s.maxDensityError,
        s.maxEscaped, scene.output.directory, pictures.empty() ? "" : "; " + pictures);
    if (s.emitted > 0 || s.removed > 0)
        fmt::print("pbf run: {} particles emitted, {} removed by outlets\n", s.emitted, s.removed);
    if (s.maxInsideSolid > 0) {
        printError(fmt::format("{} particles ended inside a solid (a solver bug): see {}/stats.csv",
                               s.maxInsideSolid, scene.output.directory));
        return 3;
    }
    if (s.maxEscaped > 0) {
        printError(fmt::format("{} particles left the domain (a solver bug): see {}/stats.csv",
                               s.maxEscaped, scene.output.directory));
        return 3;
    }
    if (args.mesh) {
        surface::MeshJob job;
        job.input = scene.output.directory;
        job.params.particleRadius = scene.simulation.particleRadius;
        job.fps = scene.fps;
        job.formats.vtk = scene.output.writeVtk;  // surfaces for ParaView beside the particles
        if (args.threads > 0) job.threads = args.threads;
        if (const int status = runMeshJob(job, args.quiet); status != 0) return status;
    }
    if (scene.output.writeUsd) {  // after the surfaces, so that the stage has them
        const std::filesystem::path dir = scene.output.directory;
        fmt::print("pbf run: usd stage of {}\n",
                   describe(exportRunUsd(dir, dir / "run.usda", args.quiet, warn, &scene)));
    }
    return 0;
}

}  // namespace

std::function<int()> addRunCommand(CLI::App& app) {
    auto args = std::make_shared<RunArguments>();
    CLI::App* run = app.add_subcommand(
        "run", "Simulate a scene and write PLY frames, stats.csv and summary.json");
    run->add_option("scene", args->scene, "Scene file (JSON, see docs/scenes.md)")->required();
    run->add_option("-o,--out", args->out,
                    "Output directory (default: the scene's output.directory)");
    run->add_option("-f,--frames", args->frames,
                    "Number of frames to simulate (overrides output.frames)")
        ->check(CLI::Range(1, 1000000));
    run->add_option("-t,--threads", args->threads, "Worker threads (default: all cores)")
        ->check(CLI::Range(1, 1024));
    run->add_option(
           "-s,--set", args->overrides,
           "Override a scene field, e.g. --set solver.iterations=8 --set fluid.viscosity=0.02")
        ->take_all();
    run->add_flag("--no-particles", args->noParticles, "Do not write PLY frames (stats only)");
    run->add_flag("--vdb-points", args->vdbPoints,
                  "Also write OpenVDB point caches frame_NNNNN.vdb (as output.vdb_points=true)");
    run->add_flag("--vtk", args->vtk,
                  "Also write VTK XML particles frame_NNNNN.vtu and particles.pvd for ParaView "
                  "(as output.vtk=true)");
    run->add_flag("--h5part", args->h5part,
                  "Also write H5Part particles frame_NNNNN.h5part and particles.h5part for "
                  "ParaView, by all ranks of a distributed run at once (as output.h5part=true)");
    run->add_flag("--usd", args->usd,
                  "At the end also write a USD stage of the run, RUN_DIR/run.usda (as "
                  "output.usd=true and `pbf export usd RUN_DIR`; with --mesh it has the surfaces)");
    run->add_flag("--mesh", args->mesh,
                  "Afterwards mesh the frames into DIR/surface (PLY + level-set .vdb, with --vtk "
                  "also .vtp; `pbf mesh` has the options)");
    run->add_option(
           "--render", args->render,
           "Render every frame while simulating: spheres or liquid (RUN_DIR/images/*.png), "
           "then RUN_DIR/<scene>.mp4 (ffmpeg) and RUN_DIR/poster.png; none turns off the "
           "scene's output.render")
        ->expected(0, 1)
        ->default_str("spheres")
        ->check(
            [](const std::string& value) -> std::string {
                if (value == "spheres" || value == "liquid" || value == "none") return {};
                // `--render` takes an optional value, so `pbf run --render SCENE`
                // reads the scene as the look.
                return "must be spheres, liquid or none, got '" + value + "'" +
                       (value.ends_with(".json")
                            ? " (that is a scene: put --render after it, or write --render=spheres)"
                            : "");
            },
            "LOOK");
    run->add_flag("--no-plot", args->noPlot,
                  "Do not plot the statistics into RUN_DIR/stats.png at the end (matplotlib)");
    run->add_flag("-q,--quiet", args->quiet, "No progress bar");
    addDeviceOption(run, args->device);
    run->add_flag(
        "-r,--resume", args->resume,
        "Continue from the checkpoint in the output directory (same scene and --set overrides); "
        "the frames are bit-identical to an uninterrupted run");
    run->add_option(
           "--checkpoint-every", args->checkpointEvery,
           "Write a checkpoint every N frames, 0: off (default: output.checkpoint_every, 10)")
        ->check(CLI::Range(0, 1000000));
    run->add_option("--checkpoint-seconds", args->checkpointSeconds,
                    "Also write one after this many wall-clock seconds, 0: off "
                    "(default: output.checkpoint_seconds, 60)")
        ->check(CLI::Range(0.0, 1e6));
    return [args] { return runScene(*args); };
}

}  // namespace pbf::cli
