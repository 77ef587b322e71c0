// Rendering without a display: an EGL context on Mesa (llvmpipe when there
// is no GPU), an offscreen framebuffer, and PNG files.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace pbf::render {

class RenderError : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

// 8-bit RGBA pixels, top row first.
struct Image {
    int width = 0;
    int height = 0;
    std::vector<std::uint8_t> rgba;
};

// Writes a PNG whole (pbf::writeFileAtomically); throws pbf::IoError naming the path.
void writePng(const std::filesystem::path& path, const Image& image);

// An OpenGL 3.3 core context made current on this thread, with no window:
// EGL on Mesa's surfaceless platform (falls back to the default display).
// Throws RenderError with what to install when EGL or GL 3.3 is missing.
class HeadlessContext {
  public:
    HeadlessContext();
    ~HeadlessContext();
    HeadlessContext(const HeadlessContext&) = delete;
    HeadlessContext& operator=(const HeadlessContext&) = delete;
    // GL_RENDERER, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)".
    std::string rendererName() const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

// An offscreen colour + depth framebuffer (4x multisampled when the driver
// allows) and its read-back. Needs a current GL context.
class OffscreenTarget {
  public:
    OffscreenTarget(int width, int height);
    ~OffscreenTarget();
    OffscreenTarget(const OffscreenTarget&) = delete;
    OffscreenTarget& operator=(const OffscreenTarget&) = delete;

    unsigned framebuffer() const;  // render into this
    int width() const { return width_; }
    int height() const { return height_; }
    Image read() const;  // resolves and reads the pixels

  private:
    int width_;
    int height_;
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

// Reads the pixels of the bound read framebuffer (e.g. a window's back buffer).
Image readFramebuffer(unsigned framebuffer, int width, int height);

}  // namespace pbf::render
