// `pbf bench`: throughput of the solver on the dam break at several sizes.
//
// For each size the dam break's particle radius is scaled so that the scene
// holds about that many particles; the solver then takes warm-up steps and
// timed steps of a fixed dt (CFL-safe for the dam break's impact speed).
// The last lines are machine-readable: one `pbf-bench:` line per size.
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "commands.hpp"
#include "console.hpp"
#include "device_option.hpp"
#include "pbf/core/distributed.hpp"
#include "pbf/core/threading.hpp"
#include "pbf/io/scene.hpp"
#include "pbf/world/world.hpp"

namespace pbf::cli {
namespace {

struct BenchArguments {
    std::string scene;
    std::vector<std::size_t> sizes{16000, 30000, 128000, 1000000};
    int steps = 20;
    int warmup = 5;
    int iterations = 0;                  // 0: the scene's solver.iterations
    std::vector<std::string> overrides;  // --set FIELD=VALUE
    int threads = 0;
    std::string device = "cpu";
    int bodies = 0;  // rigid bodies dropped into the dam break's column
};

struct BenchResult {
    std::size_t particles = 0;
    StageTimes perStep;
    double stepMs = 0.0;
    double bytesPerParticle = 0.0;
    double memoryMiB = 0.0;  // the backend's particle state and scratch (device memory on a GPU)
    double neighborsPerParticle = 0.0;
    double compactListShare = 0.0;  // blocks with 16-bit lists, of all
};

// `count` boxes of 5 cm (half of them lighter, half heavier than water) on a
// 5 x 5 x 4 lattice inside the dam break's water column (0.5 x 0.7 x 0.4 m),
// 10 cm apart: the coupling's cost with many bodies in the flow.
std::vector<RigidBodyDescription> benchBodies(int count) {
    std::vector<RigidBodyDescription> bodies;
    for (int k = 0; k < count; ++k) {
        const int i = k % 5, j = (k / 5) % 5, l = (k / 25) % 4;
        const Vec3 centre{0.05f + 0.1f * float(i), 0.07f + 0.14f * float(j),
                          0.05f + 0.1f * float(l)};
        const Vec3 half{0.025f, 0.025f, 0.025f};
        RigidBodyDescription b;
        b.shape.kind = SolidDescription::Kind::Box;
        b.shape.box = {centre - half, centre + half};
        b.density = k % 2 == 0 ? 500.0f : 1500.0f;
        bodies.push_back(b);
    }
    return bodies;
}

BenchResult benchOneSize(const Scene& base, std::size_t target, const BenchArguments& args) {
    Scene scene = base;
    const double baseCount = double(countParticles(base));
    scene.simulation.particleRadius =
        static_cast<float>(base.simulation.particleRadius * std::cbrt(baseCount / double(target)));
    if (args.iterations > 0) scene.simulation.solver.iterations = args.iterations;
    if (const std::string problem = validate(scene.simulation); !problem.empty())
        throw SceneError(fmt::format("size {}: {}", target, problem));
    // One fixed substep per frame, CFL 0.4 at the dam break's front speed
    // 2 sqrt(g H): every stepFrame() is one timed solver step.
    const float height = scene.fluidBlocks.front().box.extent().y;
    const float frontSpeed = 2.0f * std::sqrt(9.81f * height);
    const float dt = std::min(scene.simulation.solver.maxTimeStep,
                              0.4f * scene.simulation.particleSpacing() / frontSpeed);
    scene.fps = 1.0f / dt;
    scene.simulation.solver.timeStepMode = TimeStepMode::Fixed;
    scene.simulation.solver.fixedSubsteps = 1;
    scene.emitters.clear();
    scene.rigidBodies = benchBodies(args.bodies);

    WorldOptions options;
    options.backend = selectDevice(args.device);
    if (distributed::size() > 1) {
        if (options.backend != BackendKind::Cpu)
            throw SceneError("--device " + args.device +
                             ": distributed runs (mpirun -np N, N > 1) use the cpu solver");
        options.backend = BackendKind::Mpi;
    }
    World world(scene, options);
    const auto step = [&world] {
        const FrameResult r = world.stepFrame();
        if (!r.ok()) throw std::runtime_error(r.error->message);
        return r.report.stageMs;
    };
    for (int s = 0; s < args.warmup; ++s) step();

    BenchResult result;
    result.particles = world.particleCount();
    for (int s = 0; s < args.steps; ++s) result.perStep += step() * (1.0 / args.steps);
    // Distributed: a step takes as long as its slowest rank (the others wait
    // for it in the exchanges, which `exchange` counts).
    result.stepMs = distributed::maxOverRanks(result.perStep.total);
    const BackendDiagnostics d = world.backend().diagnostics();
    result.bytesPerParticle = double(d.memoryBytes) / double(result.particles);
    result.memoryMiB = double(d.memoryBytes) / double(1 << 20);
    result.neighborsPerParticle = d.neighborsPerParticle;
    result.compactListShare = d.compactListShare;
    return result;
}

std::vector<std::size_t> parseSizes(const std::string& text) {
    std::vector<std::size_t> sizes;
    std::stringstream parts(text);
    std::string part;
    while (std::getline(parts, part, ',')) {
        double value = 0.0;
        char suffix = 0;
        std::istringstream in(part);
        in >> value >> suffix;
        if (suffix == 'k' || suffix == 'K') value *= 1e3;
        if (suffix == 'm' || suffix == 'M') value *= 1e6;
        if (!(value >= 100 && value <= 1e9))
            throw CLI::ValidationError("--sizes", "sizes must be in [100, 1e9]: " + part);
        sizes.push_back(static_cast<std::size_t>(value));
    }
    return sizes;
}

int runBench(const BenchArguments& args) {
    if (args.threads > 0) setThreadCount(args.threads);
    std::vector<SceneOverride> overrides;
    for (const std::string& o : args.overrides) overrides.push_back(parseOverride(o));
    const Scene base = loadScene(args.scene, overrides);
    const SolverParams& solver = base.simulation.solver;
    const std::string iterations =
        solver.maxDensityError > 0.0f
            ? fmt::format("iterations to an average compression of {} ({} to {})",
                          solver.maxDensityError, solver.minIterations, solver.maxIterations)
            : fmt::format("{} iterations",
                          args.iterations > 0 ? args.iterations : solver.iterations);
    const bool writer = distributed::rank() == 0;  // rank 0 prints
    const int ranks = distributed::size();
    if (writer)
        fmt::print(
            "pbf bench: scene {}, {} backend, {}, {} timed steps after {} warm-up, {} "
            "threads, {} rigid bodies, {} MPI ranks\n",
            args.scene, args.device, iterations, args.steps, args.warmup, threadCount(),
            args.bodies, ranks);
    if (writer)
        fmt::print("pbf bench: device {}: {}\n", args.device,
                   deviceInfo(parseBackendKind(args.device)).description);
    if (writer)
        fmt::print(
            "{:>9} {:>9} {:>8} {:>8} {:>8} {:>8} {:>8} {:>8} {:>8} {:>8} {:>13} {:>6} {:>6} "
            "{:>8} {:>8}\n",
            "particles", "step_ms", "predict", "grid", "reorder", "lists", "lambda", "delta-p",
            "post", "bodies", "particle-st/s", "nbrs", "B/part", "MiB", "exch_ms");
    std::vector<std::string> machineLines;
    for (const std::size_t size : args.sizes) {
        const BenchResult r = benchOneSize(base, size, args);
        const double rate = double(r.particles) / (r.stepMs * 1e-3);
        const StageTimes& t = r.perStep;
        if (!writer) continue;
        fmt::print(
            "{:>9} {:>9.2f} {:>8.2f} {:>8.2f} {:>8.2f} {:>8.2f} {:>8.2f} {:>8.2f} {:>8.2f} "
            "{:>8.2f} "
            "{:>13.3e} {:>6.1f} {:>6.0f} {:>8.1f} {:>8.2f}\n",
            r.particles, r.stepMs, t.predict, t.gridBuild, t.reorder, t.neighborLists, t.lambda,
            t.deltaP, t.postProcess, t.bodies, rate, r.neighborsPerParticle, r.bytesPerParticle,
            r.memoryMiB, t.exchange);
        machineLines.push_back(fmt::format(
            "pbf-bench: particles={} steps={} iterations={:.2f} threads={} device={} "
            "step_ms={:.3f} "
            "particle_steps_per_s={:.0f} predict_ms={:.3f} neighbor_ms={:.3f} "
            "solve_ms={:.3f} post_ms={:.3f} grid_ms={:.3f} reorder_ms={:.3f} "
            "lists_ms={:.3f} lambda_ms={:.3f} deltap_ms={:.3f} bodies={} bodies_ms={:.3f} "
            "bytes_per_particle={:.0f} memory_mib={:.1f} compact_lists={:.2f} ranks={} "
            "exchange_ms={:.3f}",
            r.particles, args.steps, t.iterations, threadCount(), args.device, r.stepMs, rate,
            t.predict, t.neighborSearch, t.solve, t.postProcess, t.gridBuild, t.reorder,
            t.neighborLists, t.lambda, t.deltaP, args.bodies, t.bodies, r.bytesPerParticle,
            r.memoryMiB, r.compactListShare, ranks, t.exchange));
    }
    if (writer)
        for (const std::string& line : machineLines) fmt::print("{}\n", line);
    return 0;
}

}  // namespace

std::function<int()> addBenchCommand(CLI::App& app) {
    auto args = std::make_shared<BenchArguments>();
    auto sizes = std::make_shared<std::string>("16k,30k,128k,1M");
    args->scene = defaultScenePath("dam_break.json");
    CLI::App* bench = app.add_subcommand(
        "bench", "Measure solver throughput (particle-steps per second) on the dam break");
    bench->add_option("--scene", args->scene, "Scene to scale (default: scenes/dam_break.json)");
    bench->add_option("--sizes", *sizes, "Comma-separated particle counts, k/M suffixes allowed")
        ->capture_default_str();
    bench->add_option("--steps", args->steps, "Timed steps per size")
        ->check(CLI::Range(1, 100000))
        ->capture_default_str();
    bench->add_option("--warmup", args->warmup, "Untimed steps first")
        ->check(CLI::Range(0, 100000))
        ->capture_default_str();
    bench
        ->add_option("-i,--iterations", args->iterations,
                     "Density iterations per step (default: the scene's solver.iterations)")
        ->check(CLI::Range(1, 100));
    bench->add_option("-s,--set", args->overrides,
                      "Override a scene field, e.g. --set fluid.viscosity=0.02 (as pbf run)");
    bench->add_option("-t,--threads", args->threads, "Worker threads (default: all cores)")
        ->check(CLI::Range(1, 1024));
    addDeviceOption(bench, args->device);
    bench
        ->add_option("--bodies", args->bodies,
                     "Rigid bodies (5 cm boxes, densities 500 and 1500) in the water column: "
                     "the two-way coupling's cost")
        ->check(CLI::Range(0, 100))
        ->capture_default_str();
    return [args, sizes] {
        args->sizes = parseSizes(*sizes);
        return runBench(*args);
    };
}

}  // namespace pbf::cli
