// `pbf foam DIR`: white water (spray, foam, bubbles; Ihmsen et al. 2012)
// from the particle frames of a run, written beside them.
//
// A post-process rather than part of `pbf run`: the diffuse particles do not
// act on the water (one-way coupling, as in the paper), so they can be made
// again from the same frames with other parameters or seeds without
// simulating again, and the solver and its backends stay untouched.
#include <fmt/format.h>

#include <memory>
#include <sstream>
#include <string>

#include "commands.hpp"
#include "console.hpp"
#include "pbf/io/io.hpp"
#include "pbf/run/plot.hpp"
#include "pbf/surface/diffuse.hpp"
#include "pbf/surface/mesh_frames.hpp"

namespace pbf::cli {
namespace {

struct FoamArguments {
    std::string input;
    std::string output;
    surface::DiffuseParams params;
    float fps = 0.0f;
    bool vdb = false;
    bool quiet = false;
    bool plot = true;
};

int runFoam(const FoamArguments& a) {
    namespace fs = std::filesystem;
    const fs::path input = a.input;
    const fs::path output = a.output.empty() ? input : fs::path(a.output);
    const std::vector<surface::FrameFile> frames = surface::listParticleFrames(input, {});
    surface::DiffuseParams params = a.params;
    if (params.particleRadius <= 0.0f) params.particleRadius = surface::radiusFromSummary(input);
    if (params.particleRadius <= 0.0f)
        throw IoError((input / "summary.json").string() + ": no particle_radius; pass --radius");
    float fps = a.fps > 0.0f ? a.fps : surface::fpsFromSummary(input);
    if (fps <= 0.0f) throw IoError((input / "summary.json").string() + ": no fps; pass --fps");
    surface::DiffuseSimulator simulator(params);
    fs::create_directories(output);

    ProgressBar progress("white water", int(frames.size()), !a.quiet);
    std::ostringstream csv;
    csv << "frame,time,spray,foam,bubble,ms_per_substep\n";
    plot::Series spray{"spray", {}, {}}, foam{"foam", {}, {}}, bubble{"bubbles", {}, {}};
    plot::Series cost{"per substep", {}, {}};
    ParticleFrame previous;
    double totalSeconds = 0.0;
    for (std::size_t k = 0; k < frames.size(); ++k) {
        ParticleFrame current = readParticlesPly(frames[k].path);
        if (current.velocity.size() != current.position.size())
            throw IoError(frames[k].path.string() +
                          ": no vx vy vz (velocities) to make white water");
        if (k > 0)
            simulator.advance(frames[k - 1].frame, previous, current,
                              double(frames[k].frame - frames[k - 1].frame) / fps);
        const surface::DiffuseParticles& d = simulator.particles();
        const std::string stem = fmt::format("diffuse_{:05d}", frames[k].frame);
        surface::writeDiffusePly(output / (stem + ".ply"), d);
        if (a.vdb) surface::writeDiffuseVdb(output / (stem + ".vdb"), d);
        const double time = frames[k].frame / double(fps);
        const double ms = k > 0 ? 1e3 * simulator.lastSecondsPerSubstep() : 0.0;
        totalSeconds += k > 0 ? simulator.lastSecondsPerSubstep() * params.substeps : 0.0;
        const std::size_t counts[3] = {d.count(surface::DiffuseType::spray),
                                       d.count(surface::DiffuseType::foam),
                                       d.count(surface::DiffuseType::bubble)};
        csv << fmt::format("{},{:.6g},{},{},{},{:.3f}\n", frames[k].frame, time, counts[0],
                           counts[1], counts[2], ms);
        for (auto [series, count] : {std::pair{&spray, counts[0]}, std::pair{&foam, counts[1]},
                                     std::pair{&bubble, counts[2]}}) {
            series->x.push_back(time);
            series->y.push_back(double(count));
        }
        if (k > 0) {
            cost.x.push_back(time);
            cost.y.push_back(ms);
        }
        progress.update(int(k + 1), fmt::format("frame {} spray={} foam={} bubbles={}",
                                                frames[k].frame, counts[0], counts[1], counts[2]));
        previous = std::move(current);
    }
    progress.finish();
    const std::string table = csv.str();
    writeFileAtomically(output / "diffuse.csv", [&](std::ostream& out) { out << table; });
    std::string plotNote;
    if (a.plot) {
        plot::Figure figure{"White water of " + input.filename().string(),
                            {{"diffuse particles by type",
                              "simulated time (s)",
                              "particles",
                              {spray, foam, bubble}},
                             {"cost", "simulated time (s)", "ms per substep", {cost}}},
                            2};
        const plot::Result drawn = plot::drawFigures({{figure, output / "diffuse.png"}});
        plotNote = drawn.drawn ? fmt::format(", plot {}", (output / "diffuse.png").string())
                               : fmt::format(" (no plot: {})", drawn.message);
    }
    const surface::DiffuseParticles& d = simulator.particles();
    fmt::print(
        "pbf foam: {} frames, {} diffuse particles at the end (spray {}, foam {}, bubbles "
        "{}), {:.1f} s of diffuse work -> {}/diffuse_NNNNN.ply{}{}\n",
        frames.size(), d.size(), d.count(surface::DiffuseType::spray),
        d.count(surface::DiffuseType::foam), d.count(surface::DiffuseType::bubble), totalSeconds,
        output.string(), a.vdb ? " + .vdb" : "", plotNote);
    return 0;
}

}  // namespace

std::function<int()> addFoamCommand(CLI::App& app) {
    auto args = std::make_shared<FoamArguments>();
    CLI::App* foam = app.add_subcommand(
        "foam",
        "White water (spray, foam, air bubbles; Ihmsen et al. 2012) from the particle frames of "
        "`pbf run`: diffuse_NNNNN.ply per frame, diffuse.csv, diffuse.png; see docs/surfaces.md");
    foam->add_option("directory", args->input, "Directory of particle frames written by `pbf run`")
        ->required();
    foam->add_option("-o,--out", args->output, "Output directory (default: DIRECTORY)");
    surface::DiffuseParams& p = args->params;
    foam->add_option("--radius", p.particleRadius,
                     "Particle radius in metres (default: summary.json of `pbf run`)");
    foam->add_option("--fps", args->fps, "Frames per simulated second (default: summary.json)");
    foam->add_option("--seed", p.seed, "Random seed")->capture_default_str();
    foam->add_option("--substeps", p.substeps, "Diffuse substeps per frame")->capture_default_str();
    foam->add_option("--trapped-air-rate", p.trappedAirRate,
                     "k_ta: particles per fluid particle per second at full trapped-air potential")
        ->capture_default_str();
    foam->add_option("--wave-crest-rate", p.waveCrestRate,
                     "k_wc: particles per fluid particle per second at full wave-crest potential")
        ->capture_default_str();
    foam->add_flag("--vdb", args->vdb, "Also write diffuse_NNNNN.vdb (OpenVDB points)");
    foam->add_flag(
        "--no-plot", [args](std::int64_t) { args->plot = false; },
        "Do not plot the counts into diffuse.png");
    foam->add_flag("-q,--quiet", args->quiet, "No progress bar");
    return [args] { return runFoam(*args); };
}

}  // namespace pbf::cli
