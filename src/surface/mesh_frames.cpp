#include "pbf/surface/mesh_frames.hpp"

#include <fmt/format.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <charconv>
#include <chrono>
#include <fstream>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "pbf/io/io.hpp"
#include "pbf/io/vtk.hpp"

namespace pbf::surface {
namespace {

namespace fs = std::filesystem;

int parseInt(std::string_view text, std::string_view whole) {
    int value = 0;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (ec != std::errc() || end != text.data() + text.size())
        throw std::invalid_argument(
            fmt::format("frames: expected FIRST[:END[:STEP]] with integers, got \"{}\"", whole));
    return value;
}

std::uintmax_t sizeOf(const fs::path& path) {
    std::error_code ec;
    const std::uintmax_t size = fs::file_size(path, ec);
    return ec ? 0 : size;
}

// N of "<prefix>N<suffix>" (N at least 5 digits, as pbf names frames), else -1.
int frameNumber(std::string_view name, std::string_view prefix = "frame_",
                std::string_view suffix = ".ply") {
    if (name.size() < prefix.size() + 5 + suffix.size() || !name.starts_with(prefix) ||
        !name.ends_with(suffix))
        return -1;
    const std::string_view digits =
        name.substr(prefix.size(), name.size() - prefix.size() - suffix.size());
    int value = 0;
    const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
    if (ec != std::errc() || end != digits.data() + digits.size() ||
        digits.find_first_not_of("0123456789") != std::string_view::npos)
        return -1;
    return value;
}

}  // namespace

FrameRange parseFrameRange(std::string_view text) {
    FrameRange range;
    std::vector<std::string_view> parts;
    std::size_t start = 0;
    while (true) {
        const std::size_t colon = text.find(':', start);
        parts.push_back(
            text.substr(start, colon == std::string_view::npos ? colon : colon - start));
        if (colon == std::string_view::npos) break;
        start = colon + 1;
    }
    if (parts.size() > 3)
        throw std::invalid_argument(fmt::format("frames: too many ':' in \"{}\"", text));
    if (parts.size() == 1) {  // a single frame
        range.first = parseInt(parts[0], text);
        range.end = range.first + 1;
    } else {
        if (!parts[0].empty()) range.first = parseInt(parts[0], text);
        if (!parts[1].empty()) range.end = parseInt(parts[1], text);
        if (parts.size() == 3 && !parts[2].empty()) range.step = parseInt(parts[2], text);
    }
    if (range.first < 0)
        throw std::invalid_argument(
            fmt::format("frames: first frame must be >= 0 in \"{}\"", text));
    if (range.step < 1)
        throw std::invalid_argument(fmt::format("frames: step must be >= 1 in \"{}\"", text));
    if (parts.size() > 1 && !parts[1].empty() && range.end <= range.first)
        throw std::invalid_argument(
            fmt::format("frames: end must be greater than first in \"{}\"", text));
    return range;
}

std::vector<FrameFile> listParticleFrames(const fs::path& directory, const FrameRange& range) {
    std::error_code ec;
    if (!fs::is_directory(directory, ec))
        throw IoError(directory.string() + ": " +
                      (fs::exists(directory, ec) ? "not a directory" : "no such directory") +
                      " (expected the output directory of `pbf run`)");
    const std::vector<FrameFile> all = listFrameFiles(directory, "frame_", ".ply");
    if (all.empty())
        throw IoError(directory.string() +
                      ": no particle frames (frame_NNNNN.ply) in the directory");
    std::vector<FrameFile> frames;
    for (const FrameFile& f : all)
        if (range.contains(f.frame)) frames.push_back(f);
    if (frames.empty())
        throw IoError(fmt::format("{}: none of its {} particle frames is in the requested range",
                                  directory.string(), all.size()));
    return frames;
}

std::vector<FrameFile> listFrameFiles(const fs::path& directory, std::string_view prefix,
                                      std::string_view suffix) {
    std::vector<FrameFile> frames;
    std::error_code ec;
    if (!fs::is_directory(directory, ec)) return frames;
    for (const auto& entry : fs::directory_iterator(directory, ec))
        if (const int frame = frameNumber(entry.path().filename().string(), prefix, suffix);
            frame >= 0)
            frames.push_back({frame, entry.path()});
    if (ec) throw IoError(directory.string() + ": cannot list directory: " + ec.message());
    std::sort(frames.begin(), frames.end(),
              [](const FrameFile& a, const FrameFile& b) { return a.frame < b.frame; });
    return frames;
}

namespace {

// A positive number `field` of `directory`/summary.json, 0 if there is no
// such file or field.
float positiveFromSummary(const fs::path& directory, const char* field) {
    const fs::path file = directory / "summary.json";
    std::ifstream in(file);
    if (!in) return 0.0f;
    const nlohmann::json j = nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/false);
    if (j.is_discarded() || !j.is_object()) throw IoError(file.string() + ": not valid JSON");
    const auto it = j.find(field);
    if (it == j.end()) return 0.0f;
    if (!it->is_number() || !(it->get<double>() > 0.0))
        throw IoError(file.string() + ": " + field + ": must be a positive number");
    return it->get<float>();
}

// surface.pvd lists every surface_NNNNN.vtp of the output directory (also
// those of earlier jobs on other frame ranges), in frame order, frame k at
// k / fps. Rewritten whole after each frame: meshing a frame takes far
// longer than listing a directory.
void writeSurfaceCollection(const fs::path& output, double fps) {
    std::vector<vtk::CollectionEntry> entries;
    for (const FrameFile& f : listFrameFiles(output, "surface_", ".vtp"))
        entries.push_back({f.frame / fps, f.path.filename().string()});
    vtk::writeCollection(output / "surface.pvd", entries);
}

}  // namespace

float radiusFromSummary(const fs::path& directory) {
    return positiveFromSummary(directory, "particle_radius");
}

float fpsFromSummary(const fs::path& directory) {
    return positiveFromSummary(directory, "fps");
}

MeshFormats parseMeshFormats(std::string_view text) {
    MeshFormats f{false, false, false};
    std::size_t start = 0;
    while (start <= text.size()) {
        const std::size_t comma = std::min(text.find(',', start), text.size());
        const std::string_view word = text.substr(start, comma - start);
        if (word == "obj")
            f.obj = true;
        else if (word == "ply")
            f.ply = true;
        else if (word == "vtk")
            f.vtk = true;
        else if (word == "vdb")
            f.vdb = true;
        else
            throw std::invalid_argument(
                fmt::format("format: unknown format \"{}\" (expected ply, obj, vtk, vdb)", word));
        start = comma + 1;
    }
    return f;
}

fs::path surfaceFileName(int frame, std::string_view extension) {
    return fmt::format("surface_{:05d}.{}", frame, extension);
}
fs::path levelSetFileName(int frame) {
    return fmt::format("levelset_{:05d}.vdb", frame);
}

MeshSummary meshFrames(const MeshJob& job) {
    const auto start = std::chrono::steady_clock::now();
    std::unique_ptr<tbb::global_control> threadLimit;
    if (job.threads > 0)
        threadLimit = std::make_unique<tbb::global_control>(
            tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(job.threads));
    const std::vector<FrameFile> frames = listParticleFrames(job.input, job.range);
    MeshSummary summary;
    SurfaceParams params = job.params;
    if (params.particleRadius > 0.0f) {
        summary.radiusSource = "option";
    } else if (const float r = radiusFromSummary(job.input); r > 0.0f) {
        params.particleRadius = r;
        summary.radiusSource = "summary.json";
    } else {
        const ParticleFrame first = readParticlesPly(frames.front().path);
        try {
            params.particleRadius = estimateParticleRadius(first.position);
        } catch (const std::invalid_argument& e) {
            throw IoError(frames.front().path.string() + ": " + e.what() + "; pass --radius");
        }
        summary.radiusSource = "estimated";
    }
    summary.particleRadius = params.particleRadius;
    if (const std::string problem = validate(params); !problem.empty())
        throw std::invalid_argument(problem);
    double fps = job.fps;
    if (job.formats.vtk && !(fps > 0.0)) {
        fps = fpsFromSummary(job.input);
        if (!(fps > 0.0))
            throw IoError((job.input / "summary.json").string() +
                          ": no fps (written by `pbf run` since it writes VTK files); the frame "
                          "times of surface.pvd need it: pass --fps");
    }

    const fs::path output = job.output.empty() ? job.input / "surface" : job.output;
    std::error_code ec;
    fs::create_directories(output, ec);
    if (ec || !fs::is_directory(output))
        throw IoError(output.string() + ": cannot create output directory" +
                      (ec ? " (" + ec.message() + ")" : ""));

    for (std::size_t k = 0; k < frames.size(); ++k) {
        const FrameFile& f = frames[k];
        const ParticleFrame particles = readParticlesPly(f.path);
        const auto t0 = std::chrono::steady_clock::now();
        BuildReport build;
        const LevelSet levelSet = buildLevelSet(particles.position, params, &build);
        FrameMeshReport report;
        report.frame = f.frame;
        report.index = static_cast<int>(k);
        report.particles = build.particles;
        report.sprayDropped = build.sprayDropped;
        if (job.formats.obj || job.formats.ply || job.formats.vtk) {
            const TriangleMesh mesh = extractMesh(levelSet, params.adaptivity);
            report.vertices = mesh.vertices.size();
            report.triangles = mesh.triangles.size();
            if (job.formats.ply) {
                writeMeshPly(output / surfaceFileName(f.frame, "ply"), mesh);
                report.bytesWritten += sizeOf(output / surfaceFileName(f.frame, "ply"));
            }
            if (job.formats.obj) {
                writeMeshObj(output / surfaceFileName(f.frame, "obj"), mesh);
                report.bytesWritten += sizeOf(output / surfaceFileName(f.frame, "obj"));
            }
            if (job.formats.vtk) {
                writeMeshVtp(output / surfaceFileName(f.frame, "vtp"), mesh, f.frame / fps);
                report.bytesWritten += sizeOf(output / surfaceFileName(f.frame, "vtp"));
                writeSurfaceCollection(output, fps);
            }
        }
        if (job.formats.vdb) {
            writeLevelSetVdb(output / levelSetFileName(f.frame), levelSet);
            report.bytesWritten += sizeOf(output / levelSetFileName(f.frame));
        }
        report.seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        summary.frames += 1;
        summary.particles += report.particles;
        summary.triangles += report.triangles;
        summary.bytesWritten += report.bytesWritten;
        summary.meshSeconds += report.seconds;
        if (job.onFrame) job.onFrame(report);
    }
    summary.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return summary;
}

}  // namespace pbf::surface
