#include "pbf/render/headless.hpp"

#include <epoxy/egl.h>
#include <epoxy/gl.h>

#include <algorithm>
#include <cstring>
#include <string>

namespace pbf::render {

struct HeadlessContext::Impl {
    EGLDisplay display = EGL_NO_DISPLAY;
    EGLContext context = EGL_NO_CONTEXT;
    EGLSurface surface = EGL_NO_SURFACE;
};

namespace {

EGLDisplay openDisplay() {
    // Mesa's surfaceless platform needs neither X nor a GPU device node.
    if (epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_MESA_platform_surfaceless")) {
        EGLDisplay d =
            eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
        if (d != EGL_NO_DISPLAY) return d;
    }
    return eglGetDisplay(EGL_DEFAULT_DISPLAY);
}

std::string eglErrorText() {
    char text[32];
    std::snprintf(text, sizeof text, "EGL error 0x%04x", static_cast<unsigned>(eglGetError()));
    return text;
}

constexpr const char* kInstallHint =
    " (install the Debian packages libegl-mesa0 and libgl1-mesa-dri)";

}  // namespace

HeadlessContext::HeadlessContext() : impl_(std::make_unique<Impl>()) {
    Impl& c = *impl_;
    c.display = openDisplay();
    EGLint major = 0, minor = 0;
    if (c.display == EGL_NO_DISPLAY || eglInitialize(c.display, &major, &minor) != EGL_TRUE)
        throw RenderError("cannot open an EGL display for headless rendering: " + eglErrorText() +
                          kInstallHint);
    if (eglBindAPI(EGL_OPENGL_API) != EGL_TRUE)
        throw RenderError("EGL has no desktop OpenGL: " + eglErrorText() + kInstallHint);
    const EGLint configAttributes[] = {EGL_SURFACE_TYPE,
                                       EGL_PBUFFER_BIT,
                                       EGL_RENDERABLE_TYPE,
                                       EGL_OPENGL_BIT,
                                       EGL_RED_SIZE,
                                       8,
                                       EGL_GREEN_SIZE,
                                       8,
                                       EGL_BLUE_SIZE,
                                       8,
                                       EGL_DEPTH_SIZE,
                                       24,
                                       EGL_NONE};
    EGLConfig config = nullptr;
    EGLint count = 0;
    if (eglChooseConfig(c.display, configAttributes, &config, 1, &count) != EGL_TRUE || count < 1)
        throw RenderError("no EGL configuration for OpenGL: " + eglErrorText() + kInstallHint);
    const EGLint contextAttributes[] = {EGL_CONTEXT_MAJOR_VERSION,
                                        3,
                                        EGL_CONTEXT_MINOR_VERSION,
                                        3,
                                        EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                        EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                        EGL_NONE};
    c.context = eglCreateContext(c.display, config, EGL_NO_CONTEXT, contextAttributes);
    if (c.context == EGL_NO_CONTEXT) {
        eglTerminate(c.display);
        throw RenderError("cannot create an OpenGL 3.3 core context with EGL: " + eglErrorText() +
                          kInstallHint);
    }
    // Rendering goes to framebuffer objects; a 1x1 pbuffer only where
    // surfaceless contexts are not supported.
    if (!epoxy_has_egl_extension(c.display, "EGL_KHR_surfaceless_context")) {
        const EGLint pbufferAttributes[] = {EGL_WIDTH, 1, EGL_HEIGHT, 1, EGL_NONE};
        c.surface = eglCreatePbufferSurface(c.display, config, pbufferAttributes);
    }
    if (eglMakeCurrent(c.display, c.surface, c.surface, c.context) != EGL_TRUE) {
        eglDestroyContext(c.display, c.context);
        eglTerminate(c.display);
        throw RenderError("cannot make the EGL context current: " + eglErrorText());
    }
}

HeadlessContext::~HeadlessContext() {
    Impl& c = *impl_;
    eglMakeCurrent(c.display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    if (c.surface != EGL_NO_SURFACE) eglDestroySurface(c.display, c.surface);
    eglDestroyContext(c.display, c.context);
    eglTerminate(c.display);
    eglReleaseThread();
}

std::string HeadlessContext::rendererName() const {
    const auto* name = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    return name != nullptr ? name : "unknown";
}

struct OffscreenTarget::Impl {
    GLuint multisampleFbo = 0, resolveFbo = 0;
    GLuint multisampleColor = 0, multisampleDepth = 0, resolveColor = 0, resolveDepth = 0;
    bool multisampled = false;
};

namespace {

bool makeTarget(GLuint& fbo, GLuint& color, GLuint& depth, int samples, int w, int h) {
    glGenFramebuffers(1, &fbo);
    glGenRenderbuffers(1, &color);
    glGenRenderbuffers(1, &depth);
    glBindRenderbuffer(GL_RENDERBUFFER, color);
    glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples, GL_RGBA8, w, h);
    glBindRenderbuffer(GL_RENDERBUFFER, depth);
    glRenderbufferStorageMultisample(GL_RENDERBUFFER, samples, GL_DEPTH_COMPONENT24, w, h);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, color);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth);
    const bool complete = glCheckFramebufferStatus(GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE;
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    return complete && glGetError() == GL_NO_ERROR;
}

void destroyTarget(GLuint& fbo, GLuint& color, GLuint& depth) {
    if (fbo != 0) glDeleteFramebuffers(1, &fbo);
    if (color != 0) glDeleteRenderbuffers(1, &color);
    if (depth != 0) glDeleteRenderbuffers(1, &depth);
    fbo = color = depth = 0;
}

}  // namespace

OffscreenTarget::OffscreenTarget(int width, int height)
    : width_(width), height_(height), impl_(std::make_unique<Impl>()) {
    Impl& t = *impl_;
    if (!makeTarget(t.resolveFbo, t.resolveColor, t.resolveDepth, 0, width, height)) {
        destroyTarget(t.resolveFbo, t.resolveColor, t.resolveDepth);
        throw RenderError("cannot create a " + std::to_string(width) + "x" +
                          std::to_string(height) + " offscreen framebuffer");
    }
    // Smooth edges of spheres and lines; without MSAA support, render directly.
    t.multisampled =
        makeTarget(t.multisampleFbo, t.multisampleColor, t.multisampleDepth, 4, width, height);
    if (!t.multisampled) destroyTarget(t.multisampleFbo, t.multisampleColor, t.multisampleDepth);
}

OffscreenTarget::~OffscreenTarget() {
    destroyTarget(impl_->multisampleFbo, impl_->multisampleColor, impl_->multisampleDepth);
    destroyTarget(impl_->resolveFbo, impl_->resolveColor, impl_->resolveDepth);
}

unsigned OffscreenTarget::framebuffer() const {
    return impl_->multisampled ? impl_->multisampleFbo : impl_->resolveFbo;
}

Image OffscreenTarget::read() const {
    if (impl_->multisampled) {
        glBindFramebuffer(GL_READ_FRAMEBUFFER, impl_->multisampleFbo);
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, impl_->resolveFbo);
        glBlitFramebuffer(0, 0, width_, height_, 0, 0, width_, height_, GL_COLOR_BUFFER_BIT,
                          GL_NEAREST);
    }
    return readFramebuffer(impl_->resolveFbo, width_, height_);
}

Image readFramebuffer(unsigned framebuffer, int width, int height) {
    Image image;
    image.width = width;
    image.height = height;
    image.rgba.resize(std::size_t(width) * std::size_t(height) * 4);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, framebuffer);
    if (framebuffer == 0) glReadBuffer(GL_BACK);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, image.rgba.data());
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    // GL's first row is the bottom one; images start at the top.
    const std::size_t row = std::size_t(width) * 4;
    std::vector<std::uint8_t> swap(row);
    for (int y = 0; y < height / 2; ++y) {
        std::uint8_t* a = image.rgba.data() + std::size_t(y) * row;
        std::uint8_t* b = image.rgba.data() + std::size_t(height - 1 - y) * row;
        std::memcpy(swap.data(), a, row);
        std::memcpy(a, b, row);
        std::memcpy(b, swap.data(), row);
    }
    for (std::size_t i = 3; i < image.rgba.size(); i += 4) image.rgba[i] = 255;  // opaque
    return image;
}

}  // namespace pbf::render
