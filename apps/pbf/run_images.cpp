#include "run_images.hpp"

#include <fmt/format.h>

#include <fstream>
#include <sstream>
#include <stdexcept>

#include "pbf/io/io.hpp"

#ifdef PBF_HAVE_RENDER
#include "pbf/render/frame_images.hpp"
#include "pbf/render/headless.hpp"
#include "pbf/render/solid_mesh.hpp"
#include "pbf/render/video.hpp"
#endif

namespace pbf::cli {

namespace fs = std::filesystem;

#ifdef PBF_HAVE_RENDER

struct RunImages::Impl {
    Scene scene;
    fs::path directory;                         // the run's
    render::SolidMesh statics;                  // the static solids
    std::vector<render::SolidMesh> bodyShapes;  // rigid bodies, posed per frame
    std::vector<render::DrivenShape> driven;    // solids with a motion, placed per frame
    render::FrameImages images;
    Impl(const Scene& s, const render::ImageSettings& settings)
        : scene(s),
          directory(s.output.directory),
          statics(render::tessellateSolids(s)),
          bodyShapes(render::tessellateBodyShapes(s)),
          driven(render::tessellateDrivenSolids(s)),
          images(settings, s.simulation.domain, s.simulation.particleRadius, statics,
                 directory / "images") {}
};

std::unique_ptr<RunImages> RunImages::start(const Scene& scene,
                                            const std::function<void(const std::string&)>& warn) {
    if (!scene.output.render.enabled()) return nullptr;
    render::ImageSettings settings;
    try {
        settings = render::imageSettingsFor(scene);
    } catch (const std::invalid_argument& e) {
        throw SceneError(fmt::format("{}: output.camera_position / output.camera_target: {}",
                                     scene.source, e.what()));
    }
    try {
        std::unique_ptr<RunImages> images(new RunImages(std::make_unique<Impl>(scene, settings)));
        images->warn_ = warn;
        return images;
    } catch (const render::RenderError& e) {
        // The simulation is the product; the pictures are not worth stopping it.
        warn(fmt::format("no images: {}", e.what()));
        return nullptr;
    }
}

void RunImages::write(int frame, const World& world) {
    // Rigid bodies and driven solids move: the solids are drawn at this
    // frame's poses.
    if (!impl_->bodyShapes.empty() || !impl_->driven.empty())
        impl_->images.setSolids(
            render::posedSolids(impl_->statics, impl_->bodyShapes, impl_->driven, world));
    impl_->images.write(
        frame, render::packParticles(world.particles(), impl_->images.settings().look.color));
}

double RunImages::seconds() const {
    return impl_->images.seconds();
}

std::string RunImages::finish(const StatsTable& stats) {
    const fs::path& dir = impl_->directory;
    const fs::path frames = impl_->images.directory();
    std::string made;
    const fs::path video = dir / (impl_->scene.name + ".mp4");
    if (stats.rows() > 1) {
        const render::VideoResult v = render::encodeVideo(frames, impl_->scene.fps, video);
        if (v.written)
            made = "video " + video.string();
        else
            warn_(v.message);  // the PNG frames are the product; the video a convenience
    }
    if (made.empty()) made = "images " + (frames / "frame_*.png").string();
    const int poster = posterFrame(stats, [&](int frame) {
        std::error_code ec;
        return fs::is_regular_file(frames / render::imageFileName(frame), ec);
    });
    if (poster >= 0) {
        std::ifstream in(frames / render::imageFileName(poster), std::ios::binary);
        std::ostringstream bytes;
        bytes << in.rdbuf();
        writeFileAtomically(dir / "poster.png", [&](std::ostream& out) { out << bytes.str(); });
        made += fmt::format(", poster {} (frame {})", (dir / "poster.png").string(), poster);
    }
    return made;
}

#else  // a pbf built without pbf_render (PBF_BUILD_VIEWER=OFF)

struct RunImages::Impl {};

std::unique_ptr<RunImages> RunImages::start(const Scene& scene,
                                            const std::function<void(const std::string&)>& warn) {
    if (scene.output.render.enabled())
        warn(
            "no images: this pbf was built without rendering (PBF_BUILD_VIEWER=OFF); "
            "output.render is ignored");
    return nullptr;
}

void RunImages::write(int, const World&) {}
double RunImages::seconds() const {
    return 0.0;
}
std::string RunImages::finish(const StatsTable&) {
    return {};
}

#endif

RunImages::RunImages(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
RunImages::~RunImages() = default;

}  // namespace pbf::cli
