// Numbered PNG images of particle frames, headless: what `pbf render` and
// `pbf run --render` share (one EGL context, one renderer, one colour bar).
#pragma once

#include <filesystem>
#include <memory>
#include <string>

#include "pbf/io/scene.hpp"
#include "pbf/render/camera.hpp"
#include "pbf/render/renderer.hpp"

namespace pbf::render {

struct SolidMesh;

struct ImageSettings {
    RenderSettings look;
    int width = 960;
    int height = 540;
    Camera camera;
    bool colorBar = true;  // drawn for spheres coloured by speed or density
};

// The images a scene's `output` asks for: style, colour, size and camera
// (framing the domain where the scene gives none), the colour range that
// suits the scene. Throws std::invalid_argument with validateCamera's
// message for a camera that cannot be used (the caller says where it came from).
ImageSettings imageSettingsFor(const Scene& scene);

// The file name of frame `frame`: "frame_00042.png" (what ffmpeg reads).
std::filesystem::path imageFileName(int frame);

class FrameImages {
  public:
    // Creates the headless GL context (RenderError with what to install
    // when EGL is missing) and the output directory.
    FrameImages(const ImageSettings& settings, const Aabb& domain, float particleRadius,
                const SolidMesh& solids, std::filesystem::path directory);
    ~FrameImages();
    FrameImages(const FrameImages&) = delete;
    FrameImages& operator=(const FrameImages&) = delete;

    // Renders `particles` into directory/frame_NNNNN.png (written whole).
    void write(int frame, const RenderParticles& particles);
    // The same with white water (packDiffuse) drawn over the water.
    void write(int frame, const RenderParticles& particles, const RenderParticles& diffuse);
    // Replaces the solids drawn from the next write() on (rigid bodies move).
    void setSolids(const SolidMesh& solids);

    const ImageSettings& settings() const { return settings_; }
    const std::filesystem::path& directory() const { return directory_; }
    std::string rendererName() const;            // e.g. "llvmpipe (LLVM 15.0.6, 256 bits)"
    double seconds() const { return seconds_; }  // wall time spent in write()

  private:
    struct Impl;
    ImageSettings settings_;
    std::filesystem::path directory_;
    std::unique_ptr<Impl> impl_;
    double seconds_ = 0.0;
};

}  // namespace pbf::render
