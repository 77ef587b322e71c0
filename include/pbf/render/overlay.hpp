// The colour bar on headless images: a small Dear ImGui window in the
// top-left corner, drawn with ImGui's OpenGL 3 backend into the target
// framebuffer after the scene. Needs a current GL 3.3 context.
#pragma once

#include <memory>

#include "pbf/render/renderer.hpp"

namespace pbf::render {

class ColorBarOverlay {
  public:
    ColorBarOverlay();
    ~ColorBarOverlay();
    ColorBarOverlay(const ColorBarOverlay&) = delete;
    ColorBarOverlay& operator=(const ColorBarOverlay&) = delete;

    // Draws nothing for flat colours and the liquid look.
    void draw(unsigned framebuffer, int width, int height, const RenderSettings& settings);

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace pbf::render
