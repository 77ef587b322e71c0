#include "pbf/render/video.hpp"

#include <fmt/format.h>

#include <vector>

#include "pbf/io/io.hpp"
#include "pbf/io/process.hpp"

namespace pbf::render {

VideoResult encodeVideo(const std::filesystem::path& frameDirectory, double fps,
                        const std::filesystem::path& output) {
    VideoResult result;
    const auto ffmpeg = findProgram("ffmpeg");
    if (!ffmpeg) {
        result.programMissing = true;
        result.message =
            "ffmpeg is not installed (Debian package ffmpeg), so no video was made; "
            "the PNG frames are in " +
            frameDirectory.string();
        return result;
    }
    const std::string log = output.string() + ".log";
    const std::string partial = output.string() + ".partial.mp4";
    std::error_code ignored;
    std::filesystem::remove(log, ignored);  // a log of an earlier failure is stale now
    const ProgramResult run =
        runProgram({ffmpeg->string(), "-y", "-loglevel", "error", "-framerate",
                    fmt::format("{}", fps), "-i", (frameDirectory / "frame_%05d.png").string(),
                    // H.264 in yuv420p needs even sides; players expect yuv420p.
                    "-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2", "-c:v", "libx264", "-pix_fmt",
                    "yuv420p", "-crf", "20", partial});
    if (!run.ok()) {
        std::filesystem::remove(partial, ignored);
        writeFileAtomically(log, [&](std::ostream& out) { out << run.output; });
        result.message =
            run.started ? fmt::format("ffmpeg failed (exit status {}); see {}", run.exitStatus, log)
                        : run.output;
        return result;
    }
    // Renamed into place only when complete, like every other output file.
    std::filesystem::rename(partial, output);
    result.written = true;
    return result;
}

}  // namespace pbf::render
