// MP4 video from numbered PNG frames by running the ffmpeg program (not
// linked: Debian's `ffmpeg` package is optional at run time).
#pragma once

#include <filesystem>
#include <optional>
#include <string>

namespace pbf::render {

// The full path of `program` on $PATH, if it is there and executable.
std::optional<std::filesystem::path> findProgram(const std::string& program);

struct VideoResult {
    bool written = false;
    bool programMissing = false;  // ffmpeg is not on $PATH
    std::string message;          // why not, when not written
};

// Runs `ffmpeg -framerate FPS -i DIR/frame_%05d.png ... OUTPUT` (H.264,
// yuv420p, even image sides), logging ffmpeg's output to OUTPUT + ".log".
// Never throws for a missing or failing ffmpeg: the PNG frames stay, and the
// result says what happened.
VideoResult encodeVideo(const std::filesystem::path& frameDirectory, double fps,
                        const std::filesystem::path& output);

}  // namespace pbf::render
