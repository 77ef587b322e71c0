// The pictures of `pbf run --render` (output.render): a PNG per frame while
// the run simulates (RunOptions::writeFrame; libpbf itself draws nothing),
// then a video and a poster image at the end.
#pragma once

#include <filesystem>
#include <functional>
#include <memory>
#include <string>

#include "pbf/io/scene.hpp"
#include "pbf/run/run.hpp"
#include "pbf/world/world.hpp"

namespace pbf::cli {

class RunImages {
  public:
    // Null when the scene asks for no images, or when they cannot be made
    // (a pbf built without pbf_render, no EGL): `warn` then says why once
    // and the run goes on without them. Throws SceneError naming the file and
    // field for a camera that cannot be used.
    static std::unique_ptr<RunImages> start(const Scene& scene,
                                            const std::function<void(const std::string&)>& warn);
    ~RunImages();
    RunImages(const RunImages&) = delete;
    RunImages& operator=(const RunImages&) = delete;

    // Writes RUN_DIR/images/frame_NNNNN.png.
    void write(int frame, const World& world);

    // Encodes RUN_DIR/<scene>.mp4 from the frames (PNG frames only, with a
    // warning, where ffmpeg is missing or fails) and copies the poster frame
    // (posterFrame) to RUN_DIR/poster.png. Returns what was made, for the
    // summary line, e.g. "video out/x/x.mp4, poster out/x/poster.png".
    std::string finish(const StatsTable& stats);

    double seconds() const;  // wall time spent rendering

  private:
    struct Impl;
    explicit RunImages(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
    std::function<void(const std::string&)> warn_;
};

}  // namespace pbf::cli
