// Small owners of OpenGL objects (programs, textures, framebuffers).
// Every function needs a current GL 3.3 core context.
#pragma once

#include <epoxy/gl.h>

#include <string>

namespace pbf::render::gl {

// A linked shader program; throws std::runtime_error with the compile or link log.
class Program {
  public:
    Program() = default;
    Program(const std::string& name, const std::string& vertex, const std::string& fragment);
    ~Program();
    Program(const Program&) = delete;
    Program& operator=(const Program&) = delete;
    Program(Program&& other) noexcept;
    Program& operator=(Program&& other) noexcept;

    void use() const { glUseProgram(id_); }
    GLint uniform(const char* name) const { return glGetUniformLocation(id_, name); }

  private:
    GLuint id_ = 0;
};

// A 2D texture with nearest filtering and clamped edges.
class Texture {
  public:
    Texture() = default;
    ~Texture();
    Texture(const Texture&) = delete;
    Texture& operator=(const Texture&) = delete;
    void allocate(GLenum internalFormat, GLenum format, GLenum type, int width, int height,
                  bool linear);
    GLuint id() const { return id_; }

  private:
    GLuint id_ = 0;
};

class Framebuffer {
  public:
    Framebuffer();
    ~Framebuffer();
    Framebuffer(const Framebuffer&) = delete;
    Framebuffer& operator=(const Framebuffer&) = delete;
    // Attaches the textures (0 = none) and checks completeness; throws on failure.
    void attach(GLuint colorTexture, GLuint depthTexture);
    GLuint id() const { return id_; }

  private:
    GLuint id_ = 0;
};

// Binds a texture to a unit and the sampler uniform to that unit.
void bindTexture(const Program& program, const char* sampler, int unit, GLuint texture);

}  // namespace pbf::render::gl
