// `pbf mesh DIR`: particle frames -> water surface meshes and level sets.
#include <fmt/format.h>

#include <memory>
#include <string>

#include "commands.hpp"
#include "console.hpp"
#include "mesh_job.hpp"

namespace pbf::cli {
namespace {

struct MeshArguments {
    surface::MeshJob job;
    std::string input;
    std::string output;
    std::string formats = "ply,vdb";
    std::string frames;
    bool quiet = false;
};

}  // namespace

void addMeshOptions(CLI::App& command, surface::MeshJob& job, std::string& formats,
                    std::string& frames) {
    surface::SurfaceParams& p = job.params;
    command.add_option(
        "--radius", p.particleRadius,
        "Particle radius in metres (default: summary.json of `pbf run`, else half the median "
        "nearest-neighbour distance of the first frame)");
    command.add_option("--voxel-size", p.voxelSize, "Level-set voxel edge in particle radii")
        ->capture_default_str();
    command
        .add_option("--sphere-scale", p.sphereScale,
                    "Radius of the rasterised spheres in particle radii before eroding back to 1 r "
                    "(closes gaps)")
        ->capture_default_str();
    command
        .add_option_function<std::string>(
            "--method",
            [&p](const std::string& text) { p.method = surface::parseSurfaceMethod(text); },
            "Surface method: anisotropic (Yu & Turk 2013 ellipsoid kernels: flat water, thin "
            "sheets) or isotropic (union of spheres, closed and smoothed)")
        ->default_str("anisotropic");
    // --smooth sets the iterations of the method in use (their defaults
    // differ: the anisotropic field is smooth already).
    command.add_option_function<int>(
        "--smooth", [&p](int n) { p.smoothing = p.anisotropicSmoothing = n; },
        "Mean-curvature smoothing iterations (default: 1 anisotropic, 6 isotropic)");
    command
        .add_option("--kernel-radius", p.kernelRadius,
                    "(anisotropic) isotropic kernel radius h in particle radii")
        ->capture_default_str();
    command
        .add_option("--neighbor-radius", p.neighborRadius,
                    "(anisotropic) neighbourhood radius of the covariance in particle radii")
        ->capture_default_str();
    command
        .add_option("--centre-smoothing", p.centreSmoothing,
                    "(anisotropic) lambda of Yu & Turk's smoothed centres, 0 to 1")
        ->capture_default_str();
    command
        .add_option("--max-anisotropy", p.maxAnisotropy,
                    "(anisotropic) k_r: largest ratio of a kernel's longest to shortest axis")
        ->capture_default_str();
    command
        .add_option(
            "--min-neighbors", p.minNeighbors,
            "Particles with fewer neighbours within 4 r are spray and not meshed (0: mesh all)")
        ->capture_default_str();
    command
        .add_option("--adaptivity", p.adaptivity,
                    "Mesh adaptivity, 0 (uniform) to 1 (fewest triangles)")
        ->capture_default_str();
    command
        .add_option("--format", formats,
                    "Outputs, comma-separated: ply, obj (meshes with normals), vtk (.vtp meshes + "
                    "surface.pvd for ParaView), vdb (level set)")
        ->capture_default_str();
    command
        .add_option("--fps", job.fps,
                    "Frames per simulated second for the times in surface.pvd (default: "
                    "summary.json of `pbf run`)")
        ->check(CLI::PositiveNumber);
    command.add_option("--frames", frames,
                       "Frames to mesh as FIRST[:END[:STEP]], e.g. 0:100:2 (default: all)");
}

int runMeshJob(const surface::MeshJob& job, bool quiet) {
    const std::vector<surface::FrameFile> frames =
        surface::listParticleFrames(job.input, job.range);
    const std::filesystem::path output = job.output.empty() ? job.input / "surface" : job.output;
    if (!quiet)
        fmt::print(stderr, "pbf mesh: {} frames of {} -> {}\n", frames.size(), job.input.string(),
                   output.string());
    ProgressBar progress("meshing", static_cast<int>(frames.size()), !quiet);
    surface::MeshJob withProgress = job;
    withProgress.onFrame = [&](const surface::FrameMeshReport& r) {
        progress.update(r.index + 1,
                        fmt::format("frame {} particles={} spray={} triangles={} {:.2f}s", r.frame,
                                    r.particles, r.sprayDropped, r.triangles, r.seconds));
    };
    const surface::MeshSummary s = surface::meshFrames(withProgress);
    progress.finish();
    fmt::print(
        "pbf mesh: {} frames, {} particles (radius {:.5g} m from {}), {} triangles, {:.1f} MB "
        "written in {:.1f} s, {:.0f} particles/s meshed ({}) -> {}\n",
        s.frames, s.particles, s.particleRadius, s.radiusSource, s.triangles,
        double(s.bytesWritten) * 1e-6, s.seconds,
        s.meshSeconds > 0 ? double(s.particles) / s.meshSeconds : 0.0,
        surface::toString(job.params.method), output.string());
    return 0;
}

std::function<int()> addMeshCommand(CLI::App& app) {
    auto args = std::make_shared<MeshArguments>();
    CLI::App* mesh = app.add_subcommand("mesh",
                                        "Turn particle frames (frame_NNNNN.ply of `pbf run`) into "
                                        "water surface meshes (PLY/OBJ/VTK) and "
                                        "level sets (.vdb); see docs/surfaces.md");
    mesh->add_option("directory", args->input, "Directory of particle frames written by `pbf run`")
        ->required();
    mesh->add_option("-o,--out", args->output, "Output directory (default: DIRECTORY/surface)");
    addMeshOptions(*mesh, args->job, args->formats, args->frames);
    mesh->add_option("-t,--threads", args->job.threads, "Worker threads (default: all cores)")
        ->check(CLI::Range(1, 1024));
    mesh->add_flag("-q,--quiet", args->quiet, "No progress bar");
    return [args] {
        surface::MeshJob job = args->job;
        job.input = args->input;
        job.output = args->output;
        job.formats = surface::parseMeshFormats(args->formats);
        if (!args->frames.empty()) job.range = surface::parseFrameRange(args->frames);
        return runMeshJob(job, args->quiet);
    };
}

}  // namespace pbf::cli
