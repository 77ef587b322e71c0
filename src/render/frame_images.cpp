#include "pbf/render/frame_images.hpp"

#include <fmt/format.h>

#include <chrono>
#include <stdexcept>

#include "pbf/render/headless.hpp"
#include "pbf/render/overlay.hpp"
#include "pbf/render/solid_mesh.hpp"

namespace pbf::render {

struct FrameImages::Impl {
    HeadlessContext context;  // first: everything below needs it current
    SceneRenderer renderer;
    OffscreenTarget target;
    std::unique_ptr<ColorBarOverlay> colorBar;
    Impl(int width, int height) : target(width, height) {}
};

ImageSettings imageSettingsFor(const Scene& scene) {
    const RenderOutput& out = scene.output.render;
    ImageSettings s;
    s.look.style = parseStyle(out.style.empty() ? "spheres" : out.style);
    s.look.color = parseColorMode(out.color);
    setDefaultRange(s.look, scene.simulation);
    s.width = out.width;
    s.height = out.height;
    s.camera = frameBox(scene.simulation.domain, float(s.width) / float(s.height), out.fov);
    if (out.cameraPosition) s.camera.position = *out.cameraPosition;
    if (out.cameraTarget) s.camera.target = *out.cameraTarget;
    // The scene reader checks the fields one by one; the combination with the
    // framing camera (e.g. a given position straight above the default target)
    // is checked here.
    if (const std::string problem = validateCamera(s.camera); !problem.empty())
        throw std::invalid_argument(problem);
    return s;
}

std::filesystem::path imageFileName(int frame) {
    return fmt::format("frame_{:05d}.png", frame);
}

FrameImages::FrameImages(const ImageSettings& settings, const Aabb& domain, float particleRadius,
                         const SolidMesh& solids, std::filesystem::path directory)
    : settings_(settings), directory_(std::move(directory)) {
    std::filesystem::create_directories(directory_);
    impl_ = std::make_unique<Impl>(settings_.width, settings_.height);
    impl_->renderer.setDomain(domain);
    impl_->renderer.setParticleRadius(particleRadius);
    impl_->renderer.setSolids(solids);
    if (settings_.colorBar) impl_->colorBar = std::make_unique<ColorBarOverlay>();
}

FrameImages::~FrameImages() = default;

void FrameImages::write(int frame, const RenderParticles& particles) {
    write(frame, particles, RenderParticles{});
}

void FrameImages::write(int frame, const RenderParticles& particles,
                        const RenderParticles& diffuse) {
    const auto start = std::chrono::steady_clock::now();
    const unsigned framebuffer = impl_->target.framebuffer();
    impl_->renderer.upload(particles);
    impl_->renderer.uploadDiffuse(diffuse);
    impl_->renderer.render(framebuffer, settings_.width, settings_.height, settings_.camera,
                           settings_.look);
    if (impl_->colorBar)
        impl_->colorBar->draw(framebuffer, settings_.width, settings_.height, settings_.look);
    writePng(directory_ / imageFileName(frame), impl_->target.read());
    seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

void FrameImages::setSolids(const SolidMesh& solids) {
    impl_->renderer.setSolids(solids);
}

std::string FrameImages::rendererName() const {
    return impl_->context.rendererName();
}

}  // namespace pbf::render
