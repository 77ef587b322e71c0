// `pbf export usd RUN_DIR`: a finished run as one USD stage (RUN_DIR/run.usda
// and its per-frame layers in RUN_DIR/run_usd/), for Maya, Houdini,
// Omniverse, Blender and usdview; also what `pbf run --usd` does at its end.
//
// The stage gathers what the run directory holds: the particle frames, the
// surface meshes of `pbf mesh`, the white water of `pbf foam`, bodies.csv,
// and from the scene file the solids, the rigid bodies' shapes and the
// camera. Nothing is half-written: the per-frame layers go to a temporary
// folder that replaces the old one only when every frame is written, and
// the root layer is written (atomically) last.
#include "export_command.hpp"

#include <fmt/format.h>

#include <chrono>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "commands.hpp"
#include "console.hpp"
#include "pbf/io/io.hpp"
#include "pbf/io/scene.hpp"
#include "pbf/io/usd.hpp"
#include "pbf/run/run.hpp"
#include "pbf/surface/diffuse.hpp"
#include "pbf/surface/mesh.hpp"
#include "pbf/surface/mesh_frames.hpp"
#include "pbf/world/world.hpp"
#ifdef PBF_HAVE_RENDER
#include "pbf/render/frame_images.hpp"
#include "pbf/render/solid_mesh.hpp"
#endif

namespace pbf::cli {
namespace {

namespace fs = std::filesystem;

// What summary.json says about the run.
struct RunInfo {
    int frames = 0;  // frames 0..frames are written
    double fps = 0.0;
    float radius = 0.0f;
    std::string scene;
    fs::path sceneFile;
    std::vector<SceneOverride> overrides;  // the run's --set
};

RunInfo readRunInfo(const fs::path& run) {
    std::error_code ec;
    if (!fs::is_directory(run, ec))
        throw IoError(run.string() + ": " +
                      (fs::exists(run, ec) ? "not a directory" : "no such directory") +
                      " (expected the output directory of `pbf run`)");
    const fs::path file = run / "summary.json";
    std::ifstream in(file);
    if (!in)
        throw IoError(file.string() +
                      ": missing: not the output directory of a finished `pbf run` (a run killed "
                      "before its end is finished by `pbf run --resume`)");
    const nlohmann::json j = nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/false);
    if (j.is_discarded() || !j.is_object()) throw IoError(file.string() + ": not valid JSON");
    const auto number = [&](const char* field) {
        const auto it = j.find(field);
        if (it == j.end() || !it->is_number() || !(it->get<double>() >= 0.0))
            throw IoError(file.string() + ": " + field + ": missing or not a number >= 0");
        return it->get<double>();
    };
    RunInfo info;
    info.frames = int(number("frames"));
    info.fps = number("fps");
    info.radius = float(number("particle_radius"));
    if (!(info.fps > 0.0)) throw IoError(file.string() + ": fps: must be positive");
    info.scene = j.value("scene", std::string("run"));
    info.sceneFile = j.value("scene_file", std::string());
    if (const auto it = j.find("scene_overrides"); it != j.end()) {
        if (!it->is_array()) throw IoError(file.string() + ": scene_overrides: not a list");
        for (const nlohmann::json& o : *it) {
            if (!o.is_string())
                throw IoError(file.string() + ": scene_overrides: not a list of strings");
            info.overrides.push_back(parseOverride(o.get<std::string>()));
        }
    }
    return info;
}

// The frames <= last of "<prefix>NNNNN<suffix>" files in `directory`, ascending.
std::vector<int> framesIn(const fs::path& directory, std::string_view prefix,
                          std::string_view suffix, int last) {
    std::vector<int> frames;
    for (const surface::FrameFile& f : surface::listFrameFiles(directory, prefix, suffix))
        if (f.frame <= last) frames.push_back(f.frame);
    return frames;
}

// bodies.csv as one track per body (frames <= last).
std::vector<usd::BodyTrack> readBodies(const fs::path& file, int last) {
    std::vector<usd::BodyTrack> bodies;
    std::error_code ec;
    if (!fs::exists(file, ec)) return bodies;
    const StatsTable t = readStatsCsv(file);
    const auto& frame = t.column("frame");
    const auto& body = t.column("body");
    const std::vector<double>* c[7] = {&t.column("x"),  &t.column("y"),  &t.column("z"),
                                       &t.column("qw"), &t.column("qx"), &t.column("qy"),
                                       &t.column("qz")};
    for (std::size_t row = 0; row < t.rows(); ++row) {
        if (frame[row] > last) continue;
        const auto k = static_cast<std::size_t>(body[row]);
        if (body[row] < 0 || k > 10000)
            throw IoError(
                fmt::format("{}: row {}: bad body number {}", file.string(), row + 2, body[row]));
        if (k >= bodies.size()) bodies.resize(k + 1);
        usd::BodyTrack& b = bodies[k];
        b.frames.push_back(int(frame[row]));
        b.position.push_back({(*c[0])[row], (*c[1])[row], (*c[2])[row]});
        b.orientation.push_back({(*c[3])[row], (*c[4])[row], (*c[5])[row], (*c[6])[row]});
    }
    for (std::size_t k = 0; k < bodies.size(); ++k) bodies[k].name = fmt::format("body_{}", k);
    return bodies;
}

#ifdef PBF_HAVE_RENDER
// The renderer's unindexed triangles as a mesh (three vertices per triangle).
usd::StaticMesh toStaticMesh(const render::SolidMesh& solid, std::string name, Pose pose) {
    usd::StaticMesh m;
    m.name = std::move(name);
    m.pose = pose;
    const std::size_t n = solid.data.size() / 6;
    for (std::size_t v = 0; v < n; ++v) {
        const float* d = &solid.data[6 * v];
        m.vertices.push_back({d[0], d[1], d[2]});
        m.normals.push_back({d[3], d[4], d[5]});
    }
    for (std::uint32_t t = 0; t < n / 3; ++t) m.triangles.push_back({3 * t, 3 * t + 1, 3 * t + 2});
    return m;
}
#endif

// The solids, the bodies' shapes and the camera of the scene (the render
// library tessellates shapes and frames the camera as the run's images do).
void addSceneParts(usd::Stage& stage, const Scene& scene,
                   const std::function<void(const std::string&)>& warn) {
#ifdef PBF_HAVE_RENDER
    for (std::size_t k = 0; k < scene.solids.size(); ++k) {
        if (scene.solids[k].motion.moves())
            warn(fmt::format("{} moves (its motion): the stage shows it where it rests",
                             scene.solids[k].field));
        render::SolidMesh mesh;
        render::appendSolid(mesh, scene.solids[k], scene.simulation.domain);
        stage.solids.push_back(toStaticMesh(mesh, fmt::format("solid_{}", k), {}));
    }
    if (!scene.rigidBodies.empty() && scene.rigidBodies.size() == stage.bodies.size()) {
        // The shape's frame within the body's (centre of mass, principal
        // axes) comes from the body's mass properties, which the World
        // computes when it is built (with the scene's particles: a second
        // or so for a million).
        const World world(scene);
        const std::vector<render::SolidMesh> shapes = render::tessellateBodyShapes(scene);
        for (std::size_t k = 0; k < shapes.size(); ++k)
            stage.bodies[k].shape =
                toStaticMesh(shapes[k], "shape", world.bodyInfos()[k].shapeInBody);
    } else if (!scene.rigidBodies.empty()) {
        warn(
            fmt::format("the scene has {} rigid bodies but bodies.csv {}: no body shapes in the "
                        "stage",
                        scene.rigidBodies.size(), stage.bodies.size()));
    }
    const render::ImageSettings view = render::imageSettingsFor(scene);
    stage.camera = usd::Camera{view.camera.position, view.camera.target, view.camera.fovY,
                               float(view.width) / float(view.height)};
#else
    (void)stage;
    (void)scene;
    warn("built without pbf_render (PBF_BUILD_VIEWER=OFF): no solids, body shapes or camera");
#endif
}

// The run's scene: `given`, else the file summary.json names with the
// run's overrides.
std::optional<Scene> sceneOfRun(const Scene* given, const RunInfo& info,
                                const std::function<void(const std::string&)>& warn) {
    if (given) return *given;
    const fs::path& file = info.sceneFile;
    if (file.empty()) {
        warn("summary.json names no scene file: no solids, body shapes or camera in the stage");
        return std::nullopt;
    }
    try {
        return loadScene(file, info.overrides);
    } catch (const std::exception& e) {
        warn(std::string("no solids, body shapes or camera in the stage: ") + e.what());
        return std::nullopt;
    }
}

std::uintmax_t folderBytes(const fs::path& directory) {
    std::uintmax_t bytes = 0;
    std::error_code ec;
    for (const auto& entry : fs::recursive_directory_iterator(directory, ec))
        if (entry.is_regular_file(ec)) bytes += entry.file_size(ec);
    return bytes;
}

// Writes every series' per-frame layers and manifest, relative to `base`
// (the root layer's folder).
void writeClips(const fs::path& run, const fs::path& base, const usd::Stage& stage, float width,
                ProgressBar& progress) {
    int done = 0;
    for (const usd::ClipSeries& s : stage.series) {
        fs::create_directories(base / s.directory);
        for (const int frame : s.frames) {
            const fs::path layer = base / usd::clipLayerName(s, frame);
            std::size_t count = 0;
            if (s.name == "particles") {
                const ParticleFrame p = readParticlesPly(run / frameFileName(frame));
                usd::writePointsClip(layer, s.name, frame,
                                     {p.position, p.velocity, p.id, p.density, {}, width});
                count = p.position.size();
            } else if (s.name == "surface") {
                const surface::TriangleMesh m =
                    surface::readMeshPly(run / "surface" / surface::surfaceFileName(frame, "ply"));
                usd::writeMeshClip(layer, s.name, frame, {m.vertices, m.normals, m.triangles});
                count = m.triangles.size();
            } else {
                const surface::DiffuseParticles d =
                    surface::readDiffusePly(run / fmt::format("diffuse_{:05d}.ply", frame));
                std::vector<std::uint8_t> kind(d.type.size());
                for (std::size_t i = 0; i < kind.size(); ++i)
                    kind[i] = static_cast<std::uint8_t>(d.type[i]);
                usd::writePointsClip(layer, s.name, frame,
                                     {d.position, d.velocity, d.id, {}, kind, width});
                count = d.size();
            }
            progress.update(++done, fmt::format("{} {} ({})", s.name, frame, count));
        }
        usd::writeClipManifest(base, s);
    }
}

}  // namespace

UsdExport exportRunUsd(const fs::path& run, const fs::path& rootFile, bool quiet,
                       const std::function<void(const std::string&)>& warn, const Scene* scene) {
    const auto start = std::chrono::steady_clock::now();
    const RunInfo info = readRunInfo(run);
    // Every particle frame of the run must be there; surfaces and white
    // water where they were made.
    std::vector<int> frames;
    for (int frame = 0; frame <= info.frames; ++frame) {
        const fs::path file = run / frameFileName(frame);
        std::error_code ec;
        if (!fs::is_regular_file(file, ec))
            throw IoError(
                fmt::format("{}: missing (summary.json says the run wrote frames 0 to "
                            "{}; `pbf run --no-particles` writes none)",
                            file.string(), info.frames));
        frames.push_back(frame);
    }
    const std::vector<int> surfaceFrames =
        framesIn(run / "surface", "surface_", ".ply", info.frames);
    const std::vector<int> foamFrames = framesIn(run, "diffuse_", ".ply", info.frames);

    const std::string stem = rootFile.stem().string();
    const std::string folder = stem + "_usd";
    usd::Stage stage;
    stage.doc = fmt::format("pbf run of scene {}: {} frames at {} fps (pbf export usd)", info.scene,
                            info.frames + 1, info.fps);
    stage.fps = info.fps;
    stage.startFrame = 0;
    stage.endFrame = info.frames;
    stage.series.push_back({"particles", "Points", frames, folder + "/particles",
                            usd::pointsAttributes(true, true, true, false)});
    if (!surfaceFrames.empty())
        stage.series.push_back(
            {"surface", "Mesh", surfaceFrames, folder + "/surface", usd::meshAttributes(true)});
    if (!foamFrames.empty())
        stage.series.push_back({"whitewater", "Points", foamFrames, folder + "/whitewater",
                                usd::pointsAttributes(true, true, false, true)});
    stage.bodies = readBodies(run / "bodies.csv", info.frames);
    if (const std::optional<Scene> loaded = sceneOfRun(scene, info, warn))
        addSceneParts(stage, *loaded, warn);

    // The per-frame layers in a new folder; it replaces the old one only
    // when all are written, then the root layer that names them.
    const fs::path directory = rootFile.parent_path().empty() ? "." : rootFile.parent_path();
    const fs::path final = directory / folder;
    const fs::path temporary =
        directory / fmt::format(".{}.tmp{}", folder, std::random_device()() % 1000000);
    ProgressBar progress("usd", int(frames.size() + surfaceFrames.size() + foamFrames.size()),
                         !quiet);
    const fs::path old =
        directory / fmt::format(".{}.old{}", folder, std::random_device()() % 1000000);
    bool movedOld = false, movedNew = false;
    try {
        usd::Stage inTemporary = stage;
        for (usd::ClipSeries& s : inTemporary.series)
            s.directory = temporary.filename().string() + s.directory.substr(folder.size());
        writeClips(run, directory, inTemporary, 2.0f * info.radius, progress);
        progress.finish();
        std::error_code ec;
        if (fs::exists(final, ec)) {
            fs::rename(final, old);
            movedOld = true;
        }
        fs::rename(temporary, final);
        movedNew = true;
        usd::writeRootLayer(rootFile, stage);
        fs::remove_all(old, ec);
    } catch (...) {
        // Back to how it was: the old root layer (rewritten whole or not at
        // all) names the old per-frame layers.
        std::error_code ec;
        fs::remove_all(movedNew ? final : temporary, ec);
        if (movedOld) fs::rename(old, final, ec);
        throw;
    }
    UsdExport result;
    result.frames = int(frames.size());
    result.surfaceFrames = int(surfaceFrames.size());
    result.foamFrames = int(foamFrames.size());
    result.bodies = int(stage.bodies.size());
    result.solids = int(stage.solids.size());
    std::error_code ec;
    result.bytes = folderBytes(final) + fs::file_size(rootFile, ec);
    result.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    result.root = rootFile;
    return result;
}

std::string describe(const UsdExport& e) {
    return fmt::format(
        "{} particle frames, {} surface frames, {} white-water frames, {} bodies, {} solids: "
        "{:.1f} MB in {:.1f} s -> {}",
        e.frames, e.surfaceFrames, e.foamFrames, e.bodies, e.solids, double(e.bytes) * 1e-6,
        e.seconds, e.root.string());
}

std::function<int()> addExportCommand(CLI::App& app) {
    struct Arguments {
        std::string format;
        std::string input;
        std::string output;
        std::string scene;
        std::vector<std::string> overrides;
        bool quiet = false;
    };
    auto args = std::make_shared<Arguments>();
    CLI::App* command = app.add_subcommand(
        "export",
        "Write a finished run in another format: usd (one stage for Maya, Houdini, Omniverse, "
        "Blender, usdview: RUN_DIR/run.usda; see docs/clients.md)");
    command->add_option("format", args->format, "Format: usd")
        ->required()
        ->check(CLI::IsMember({"usd"}));
    command->add_option("directory", args->input, "Output directory of `pbf run`")->required();
    command->add_option("-o,--out", args->output,
                        "Root layer to write (default: DIRECTORY/run.usda); the per-frame layers "
                        "go beside it in <name>_usd/");
    command->add_option("--scene", args->scene,
                        "Scene file for the solids, bodies' shapes and camera (default: the one "
                        "summary.json names)");
    command
        ->add_option("-s,--set", args->overrides,
                     "Scene overrides after the run's own (which summary.json records)")
        ->take_all();
    command->add_flag("-q,--quiet", args->quiet, "No progress bar");
    return [args] {
        const fs::path run = args->input;
        const fs::path root = args->output.empty() ? run / "run.usda" : fs::path(args->output);
        if (root.extension() != ".usda")
            throw IoError(root.string() + ": the root layer must end in .usda");
        std::optional<Scene> scene;
        if (!args->scene.empty() || !args->overrides.empty()) {
            // The run's overrides, then the command line's.
            const RunInfo info = readRunInfo(run);
            std::vector<SceneOverride> overrides = info.overrides;
            for (const std::string& o : args->overrides) overrides.push_back(parseOverride(o));
            scene =
                loadScene(!args->scene.empty() ? fs::path(args->scene) : info.sceneFile, overrides);
        }
        const UsdExport e = exportRunUsd(
            run, root, args->quiet,
            [](const std::string& m) { fmt::print(stderr, "pbf: warning: {}\n", m); },
            scene ? &*scene : nullptr);
        fmt::print("pbf export: usd stage of {}\n", describe(e));
        return 0;
    };
}

}  // namespace pbf::cli
