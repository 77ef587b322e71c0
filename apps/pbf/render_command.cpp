// `pbf render`: images (PNG) and video (MP4 through ffmpeg) without a display,
// from a scene (simulate and render) or a directory of PLY frames.
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "commands.hpp"
#include "console.hpp"
#include "device_option.hpp"
#include "pbf/core/threading.hpp"
#include "pbf/io/io.hpp"
#include "pbf/io/scene.hpp"
#include "pbf/render/camera.hpp"
#include "pbf/render/frame_images.hpp"
#include "pbf/render/renderer.hpp"
#include "pbf/render/solid_mesh.hpp"
#include "pbf/render/video.hpp"
#include "pbf/run/run.hpp"
#include "pbf/surface/diffuse.hpp"
#include "pbf/world/world.hpp"

namespace pbf::cli {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

struct RenderArguments {
    std::string scene;
    std::string plyDirectory;
    std::string out;
    int frames = -1;
    // Unset: the scene's output.* image fields (docs/scenes.md), else their defaults.
    std::optional<int> width;
    std::optional<int> height;
    std::string cameraPosition;
    std::string cameraTarget;
    std::optional<float> fov;
    std::optional<std::string> style;
    std::optional<std::string> color;
    std::string range;
    bool noVideo = false;
    bool noBox = false;
    bool noColorBar = false;
    int threads = 0;
    std::vector<std::string> overrides;
    bool quiet = false;
    std::string device = "cpu";
};

Vec3 parseVec3(const std::string& option, const std::string& text) {
    std::stringstream in(text);
    Vec3 v;
    char c1 = 0, c2 = 0;
    if (!(in >> v.x >> c1 >> v.y >> c2 >> v.z) || c1 != ',' || c2 != ',' || !in.eof() ||
        !std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z))
        throw CLI::ValidationError(option, "expected three numbers X,Y,Z, got '" + text + "'");
    return v;
}

std::vector<fs::path> plyFrames(const fs::path& directory) {
    if (!fs::is_directory(directory))
        throw IoError(directory.string() + ": not a directory of PLY frames");
    std::vector<fs::path> files;
    // frame_<digits>.ply (std::regex trips GCC 12's -Wmaybe-uninitialized under ASan).
    const auto isFrame = [](const std::string& name) {
        const std::string prefix = "frame_", suffix = ".ply";
        if (name.size() <= prefix.size() + suffix.size() || !name.starts_with(prefix) ||
            !name.ends_with(suffix))
            return false;
        const std::string digits =
            name.substr(prefix.size(), name.size() - prefix.size() - suffix.size());
        return std::all_of(digits.begin(), digits.end(),
                           [](char c) { return c >= '0' && c <= '9'; });
    };
    for (const auto& entry : fs::directory_iterator(directory))
        if (entry.is_regular_file() && isFrame(entry.path().filename().string()))
            files.push_back(entry.path());
    std::sort(files.begin(), files.end());
    if (files.empty()) throw IoError(directory.string() + ": no frame_NNNNN.ply files");
    return files;
}

// Body poses per frame from a run's bodies.csv (frame,time,body,x,y,z,qw,qx,qy,qz,...):
// poses[frame][body] is the pose of the body's centre of mass and principal axes.
std::vector<std::vector<Pose>> readBodyPoses(const fs::path& file) {
    std::ifstream in(file);
    if (!in) throw IoError(file.string() + ": cannot open");
    std::vector<std::vector<Pose>> poses;
    std::string line;
    std::getline(in, line);  // header
    int row = 1;
    while (std::getline(in, line)) {
        ++row;
        std::stringstream fields(line);
        std::vector<double> v;
        std::string field;
        while (std::getline(fields, field, ',')) v.push_back(std::atof(field.c_str()));
        if (v.size() < 10 || v[0] < 0 || v[2] < 0)
            throw IoError(fmt::format("{}: line {}: expected frame,time,body,x,y,z,qw,qx,qy,qz",
                                      file.string(), row));
        const auto frame = std::size_t(v[0]), body = std::size_t(v[2]);
        if (poses.size() <= frame) poses.resize(frame + 1);
        if (poses[frame].size() <= body) poses[frame].resize(body + 1);
        poses[frame][body] = {{float(v[3]), float(v[4]), float(v[5])},
                              {float(v[6]), float(v[7]), float(v[8]), float(v[9])}};
    }
    return poses;
}

// White water of a PLY frame: pbf foam's diffuse_NNNNN.ply beside
// frame_NNNNN.ply (same number), packed for the renderer; none without it.
render::RenderParticles diffuseFor(const fs::path& frameFile) {
    const fs::path file =
        frameFile.parent_path() /
        ("diffuse_" + frameFile.filename().string().substr(std::string("frame_").size()));
    if (!fs::exists(file)) return {};
    const surface::DiffuseParticles d = surface::readDiffusePly(file);
    std::vector<std::uint8_t> types(d.size());
    for (std::size_t k = 0; k < d.size(); ++k) types[k] = std::uint8_t(d.type[k]);
    return render::packDiffuse(d.position, types);
}

Aabb boundingBox(const ParticleFrame& frame) {
    Aabb box{{1e30f, 1e30f, 1e30f}, {-1e30f, -1e30f, -1e30f}};
    for (const Vec3& p : frame.position) {
        box.min = {std::min(box.min.x, p.x), std::min(box.min.y, p.y), std::min(box.min.z, p.z)};
        box.max = {std::max(box.max.x, p.x), std::max(box.max.y, p.y), std::max(box.max.z, p.z)};
    }
    if (frame.position.empty()) box = Aabb{{0, 0, 0}, {1, 1, 1}};
    return box;
}

// The command's image options written into the scene's output.render, so
// that one function (render::imageSettingsFor) turns either into images.
void applyImageOptions(const RenderArguments& args, RenderOutput& render) {
    if (args.style) render.style = *args.style;
    if (render.style.empty()) render.style = "spheres";
    if (args.color) render.color = *args.color;
    if (args.width) render.width = *args.width;
    if (args.height) render.height = *args.height;
    if (args.fov) render.fov = *args.fov;
    if (!args.cameraPosition.empty())
        render.cameraPosition = parseVec3("--camera-position", args.cameraPosition);
    if (!args.cameraTarget.empty())
        render.cameraTarget = parseVec3("--camera-target", args.cameraTarget);
}

int runRender(const RenderArguments& args) {
    if (args.scene.empty() && args.plyDirectory.empty())
        throw std::invalid_argument(
            "give a scene file to simulate, or --ply DIR (a directory of PLY frames)");
    const bool simulate = args.plyDirectory.empty();
    if (const std::string problem =
            render::validateResolution(args.width.value_or(960), args.height.value_or(540));
        !problem.empty())
        throw std::invalid_argument(problem);
    if (args.fov && !(*args.fov >= 1.0f && *args.fov <= 170.0f))
        throw std::invalid_argument(
            fmt::format("camera.fov: must be in [1, 170] degrees, got {}", *args.fov));
    if (args.style) render::parseStyle(*args.style);
    if (args.color) render::parseColorMode(*args.color);

    // The scene gives domain, radius, solids, colour range and the image
    // fields of its output; PLY frames may come without one.
    std::vector<fs::path> plyFiles;
    ParticleFrame firstFrame;
    if (!args.plyDirectory.empty()) {
        plyFiles = plyFrames(args.plyDirectory);
        if (args.frames > 0 && std::size_t(args.frames) < plyFiles.size())
            plyFiles.resize(std::size_t(args.frames));
        firstFrame = readParticlesPly(plyFiles.front());
    }
    Scene scene;
    const bool haveScene = !args.scene.empty();
    if (haveScene) {
        std::vector<SceneOverride> overrides;
        for (const std::string& o : args.overrides) overrides.push_back(parseOverride(o));
        scene = loadScene(args.scene, overrides);
    } else {
        scene.name = fs::path(args.plyDirectory).filename().string();
        scene.simulation.domain = boundingBox(firstFrame);
        scene.simulation.particleRadius = 0.01f;  // the default lattice radius; PLY carries none
    }
    applyImageOptions(args, scene.output.render);
    render::ImageSettings images = render::imageSettingsFor(scene);
    images.look.drawBox = !args.noBox;
    images.colorBar = !args.noColorBar;
    if (!args.range.empty()) {
        std::stringstream in(args.range);
        char comma = 0;
        render::RenderSettings& look = images.look;
        if (!(in >> look.rangeMin >> comma >> look.rangeMax) || comma != ',' || !in.eof() ||
            !(look.rangeMax > look.rangeMin))
            throw CLI::ValidationError("--range",
                                       "expected MIN,MAX with MIN < MAX, got '" + args.range + "'");
    }

    const std::string& name = scene.name;
    const std::string style = scene.output.render.style;
    const fs::path out =
        !args.out.empty()
            ? fs::path(args.out)
            : fs::path("out") / fmt::format("{}_{}", name.empty() ? "frames" : name, style);
    const int total = simulate ? (args.frames >= 0 ? args.frames : scene.output.frames) + 1
                               : int(plyFiles.size());
    const double fps = haveScene ? scene.fps : 30.0;
    if (args.threads > 0) setThreadCount(args.threads);

    // Solids are drawn from the scene, also for PLY frames.
    const render::SolidMesh solids =
        haveScene ? render::tessellateSolids(scene) : render::SolidMesh{};
    render::FrameImages writer(images, scene.simulation.domain, scene.simulation.particleRadius,
                               solids, out);
    if (!args.quiet)
        fmt::print(stderr,
                   "pbf render: {} frames of {}, {}x{}, {} look, colour by {}, on {} -> {}\n",
                   total, name, images.width, images.height, style, scene.output.render.color,
                   writer.rendererName(), out.string());

    ProgressBar progress("rendering", total, !args.quiet);
    const auto renderFrame = [&](int frame, const render::RenderParticles& particles,
                                 const render::RenderParticles& diffuse) {
        writer.write(frame, particles, diffuse);
        progress.update(frame + 1, diffuse.count() > 0
                                       ? fmt::format("{} particles, {} white water",
                                                     particles.count(), diffuse.count())
                                       : fmt::format("{} particles", particles.count()));
    };
    int status = 0;
    double simulateSeconds = 0.0;
    if (simulate) {
        // `pbf run`'s loop with an image instead of a PLY file per frame
        // (stats.csv and summary.json go beside the images).
        Scene run = scene;
        run.output.directory = out.string();
        run.output.frames = total - 1;
        run.output.writeParticles = false;
        run.output.writeVdbPoints = false;
        run.output.writeVtk = false;
        run.output.writeCheckpoints = false;
        RunOptions options;
        options.world.backend = selectDevice(args.device);
        const render::SolidMesh& statics = solids;
        const std::vector<render::SolidMesh> bodyShapes = render::tessellateBodyShapes(scene);
        const std::vector<render::DrivenShape> driven = render::tessellateDrivenSolids(scene);
        options.writeFrame = [&](int frame, const World& world) {
            // Rigid bodies and driven solids move: the solids are drawn at
            // this frame's poses.
            if (!bodyShapes.empty() || !driven.empty())
                writer.setSolids(render::posedSolids(statics, bodyShapes, driven, world));
            renderFrame(frame, render::packParticles(world.particles(), images.look.color), {});
        };
        const auto t0 = Clock::now();
        const RunSummary summary = runScene(run, options);
        simulateSeconds =
            std::chrono::duration<double>(Clock::now() - t0).count() - writer.seconds();
        if (summary.error) {
            progress.finish();
            printError(summary.error->message);
            status = 4;
        }
    } else {
        // Rigid bodies of the scene, placed per frame from the run's bodies.csv
        // (centre of mass and principal axes; the World built from the scene
        // gives where each shape sits in its body frame).
        std::vector<render::SolidMesh> bodyShapes;
        std::vector<Pose> shapeInBody;
        std::vector<std::vector<Pose>> bodyPoses;
        const fs::path bodiesCsv = fs::path(args.plyDirectory) / "bodies.csv";
        if (haveScene && !scene.rigidBodies.empty() && fs::exists(bodiesCsv)) {
            bodyShapes = render::tessellateBodyShapes(scene);
            const World world(scene);
            for (const RigidBodyInfo& info : world.bodyInfos())
                shapeInBody.push_back(info.shapeInBody);
            bodyPoses = readBodyPoses(bodiesCsv);
        }
        const render::SolidMesh& statics = solids;
        // Driven solids: their motion is a function of the frame's time.
        const std::vector<render::DrivenShape> driven =
            haveScene ? render::tessellateDrivenSolids(scene) : std::vector<render::DrivenShape>{};
        for (int frame = 0; frame < total; ++frame) {
            const auto t0 = Clock::now();
            const ParticleFrame ply =
                frame == 0 ? firstFrame : readParticlesPly(plyFiles[std::size_t(frame)]);
            if (std::size_t(frame) < bodyPoses.size() || !driven.empty()) {
                render::SolidMesh posed = statics;
                render::appendDriven(posed, driven, double(frame) / fps);
                const std::vector<Pose> poses = std::size_t(frame) < bodyPoses.size()
                                                    ? bodyPoses[std::size_t(frame)]
                                                    : std::vector<Pose>{};
                for (std::size_t k = 0; k < bodyShapes.size() && k < poses.size(); ++k) {
                    const Pose& b = poses[k];
                    const Pose& local = shapeInBody[k];
                    render::appendPosed(
                        posed, bodyShapes[k],
                        {b.toWorld(local.position), b.orientation * local.orientation});
                }
                writer.setSolids(posed);
            }
            const render::RenderParticles diffuse = diffuseFor(plyFiles[std::size_t(frame)]);
            simulateSeconds += std::chrono::duration<double>(Clock::now() - t0).count();
            renderFrame(frame, render::packParticles(ply, images.look.color), diffuse);
        }
    }
    progress.finish();

    std::string videoText = "no video (--no-video)";
    if (!args.noVideo && total > 1) {
        const fs::path video = out / fmt::format("{}.mp4", name.empty() ? "frames" : name);
        const render::VideoResult v = render::encodeVideo(out, fps, video);
        if (v.written) {
            videoText = "video " + video.string();
        } else if (v.programMissing) {
            // Not an error: the frames are the product, the video a convenience.
            videoText = "no video (ffmpeg missing)";
            fmt::print(stderr, "pbf: warning: {}\n", v.message);
        } else {
            videoText = "no video";
            printError(v.message);
            status = 4;
        }
    } else if (total <= 1) {
        videoText = "no video (one frame)";
    }
    fmt::print(
        "pbf render: {} frames {}x{} ({}) -> {}/frame_*.png, {}; {} {:.2f} s, "
        "render {:.2f} s ({:.1f} ms per frame, PNG writing included)\n",
        total, images.width, images.height, style, out.string(), videoText,
        simulate ? "simulate" : "read PLY", simulateSeconds, writer.seconds(),
        1e3 * writer.seconds() / total);
    return status;
}

}  // namespace

std::function<int()> addRenderCommand(CLI::App& app) {
    auto args = std::make_shared<RenderArguments>();
    CLI::App* cmd = app.add_subcommand(
        "render",
        "Render PNG frames and an MP4 video without a display (EGL), from a scene or PLY frames");
    cmd->add_option("scene", args->scene,
                    "Scene to simulate and render (JSON, see docs/scenes.md); with --ply "
                    "only its domain, particle radius, solids and colour range are used");
    cmd->add_option("--ply", args->plyDirectory,
                    "Render the frame_NNNNN.ply files of this directory instead (with the "
                    "white water of pbf foam's diffuse_NNNNN.ply where present)");
    cmd->add_option("-o,--out", args->out, "Output directory (default: out/<name>_<style>)");
    cmd->add_option("-f,--frames", args->frames,
                    "Scene: frames to simulate after the initial one (default: output.frames); "
                    "PLY: at most this many files")
        ->check(CLI::Range(0, 1000000));
    cmd->add_option(
        "--width", args->width,
        "Image width in pixels [16, 8192] (default: the scene's output.image_size, 960)");
    cmd->add_option("--height", args->height,
                    "Image height in pixels [16, 8192] (default: the scene's, 540)");
    cmd->add_option("--camera-position", args->cameraPosition,
                    "Camera position X,Y,Z in metres (default: the scene's "
                    "output.camera_position, else framing the domain)");
    cmd->add_option("--camera-target", args->cameraTarget,
                    "Point the camera looks at, X,Y,Z (default: the scene's "
                    "output.camera_target, else the domain centre)");
    cmd->add_option("--fov", args->fov,
                    "Vertical field of view in degrees [1, 170] (default: the scene's, 40)");
    cmd->add_option("--style", args->style,
                    "spheres (impostors) or liquid (screen-space fluid) (default: the scene's "
                    "output.render, else spheres)");
    cmd->add_option("--color", args->color,
                    "Sphere colour: speed, density or flat (default: the scene's, speed)");
    cmd->add_option("--range", args->range,
                    "Colour map range MIN,MAX (m/s or kg/m^3; default from the scene)");
    cmd->add_flag("--no-video", args->noVideo, "Only PNG frames, no MP4");
    cmd->add_flag("--no-box", args->noBox, "Do not draw the domain box");
    cmd->add_flag("--no-color-bar", args->noColorBar,
                  "No colour bar in the top-left corner (spheres coloured by speed or density)");
    cmd->add_option("-t,--threads", args->threads, "Simulation threads (default: all cores)")
        ->check(CLI::Range(1, 1024));
    cmd->add_option("-s,--set", args->overrides,
                    "Override a scene field, e.g. --set solver.iterations=8")
        ->take_all();
    cmd->add_flag("-q,--quiet", args->quiet, "No progress bar");
    addDeviceOption(cmd, args->device);
    return [args] { return runRender(*args); };
}

}  // namespace pbf::cli
