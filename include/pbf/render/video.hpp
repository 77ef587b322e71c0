// MP4 video from numbered PNG frames by running the ffmpeg program (not
// linked: Debian's `ffmpeg` package is optional at run time).
#pragma once

#include <filesystem>
#include <string>

namespace pbf::render {

struct VideoResult {
    bool written = false;
    bool programMissing = false;  // ffmpeg is not on $PATH
    std::string message;          // why not, when not written
};

// Runs `ffmpeg -framerate FPS -i DIR/frame_%05d.png ... OUTPUT` (H.264,
// yuv420p, even image sides). On failure ffmpeg's output goes to
// OUTPUT + ".log". Never throws for a missing or failing ffmpeg: the PNG
// frames stay, and the result says what happened.
VideoResult encodeVideo(const std::filesystem::path& frameDirectory, double fps,
                        const std::filesystem::path& output);

}  // namespace pbf::render
