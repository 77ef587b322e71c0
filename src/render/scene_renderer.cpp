// SceneRenderer: the sphere and liquid looks (see renderer.hpp).
#include <algorithm>
#include <cmath>
#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "gl_util.hpp"
#include "pbf/render/renderer.hpp"
#include "pbf/render/solid_mesh.hpp"
#include "pbf/surface/anisotropic.hpp"
#include "pbf/world/local_frame.hpp"
#include "shaders.hpp"

namespace pbf::render {
namespace {

std::string fragment(std::initializer_list<const char*> parts) {
    std::string source = "#version 330 core\n";
    for (const char* part : parts) source += part;
    return source;
}

glm::vec3 toGlm(const Vec3& v) {
    return {v.x, v.y, v.z};
}

// Matrices and derived values of one camera at one aspect ratio.
struct View {
    glm::mat4 view;
    glm::mat4 proj;
    glm::mat3 viewToWorld;
    glm::vec2 tanHalf;
    glm::vec3 lightView;
    glm::vec3 lightWorld;
    glm::vec3 eye;
    float pixelsPerMetre;  // at 1 m depth
};

View makeView(const Camera& camera, const Aabb& domain, int width, int height) {
    View v{};
    const float aspect = float(width) / float(height);
    const float fov = camera.fovY * std::numbers::pi_v<float> / 180.0f;
    v.view = glm::lookAt(toGlm(camera.position), toGlm(camera.target), glm::vec3(0.0f, 1.0f, 0.0f));
    // Near and far planes bracket the domain (with a margin for the floor).
    const float distance = glm::length(toGlm(camera.target) - toGlm(camera.position));
    const float extent = glm::length(toGlm(domain.extent()));
    const float farPlane = distance + 4.0f * extent + 1.0f;
    const float nearPlane = std::max(1e-3f, farPlane * 1e-4f);
    v.proj = glm::perspective(fov, aspect, nearPlane, farPlane);
    v.viewToWorld = glm::transpose(glm::mat3(v.view));
    v.tanHalf = {std::tan(0.5f * fov) * aspect, std::tan(0.5f * fov)};
    v.lightWorld = glm::normalize(glm::vec3(0.35f, 0.85f, 0.45f));
    v.lightView = glm::normalize(glm::mat3(v.view) * v.lightWorld);
    v.eye = toGlm(camera.position);
    v.pixelsPerMetre = 0.5f * float(height) / v.tanHalf.y;
    return v;
}

// Depth-splat sphere radius of the liquid look, in particle radii.
constexpr float kLiquidRadiusScale = 1.8f;
// Anisotropic splats: a particle with too few neighbours for a covariance
// (spray, a stream one particle wide) is a sphere of this many radii, so that
// neighbours 2 r apart along a stream overlap into one line of water.
constexpr float kIsolatedSplatScale = 1.2f;
// The least thickness of water a covered pixel is tinted as, in particle
// radii: a stream or sheet one particle thick stays visible.
constexpr float kMinThicknessScale = 4.0f;
// White water spheres, in particle radii.
constexpr float kDiffuseRadiusScale = 0.7f;

// Per particle 16 floats for the ellipsoid depth splats: the smoothed centre
// and the bounding radius, then the rows of G (each padded to 4 floats). The
// Yu & Turk kernels (radius h inside the water) are scaled so that a particle
// inside the water gets the sphere splat of kLiquidRadiusScale radii.
std::vector<float> splatEllipsoids(const std::vector<float>& packed, float radius) {
    const std::size_t n = packed.size() / 4;
    std::vector<Vec3> positions(n);
    for (std::size_t i = 0; i < n; ++i)
        positions[i] = {packed[4 * i], packed[4 * i + 1], packed[4 * i + 2]};
    surface::SurfaceParams params;
    params.particleRadius = radius;
    const std::vector<surface::Ellipsoid> kernels = surface::computeEllipsoids(positions, params);
    const float scale = kLiquidRadiusScale / params.kernelRadius;
    std::vector<float> out(16 * n, 0.0f);
    for (std::size_t i = 0; i < n; ++i) {
        const surface::Ellipsoid& e = kernels[i];
        float* o = &out[16 * i];
        o[0] = e.centre.x;
        o[1] = e.centre.y;
        o[2] = e.centre.z;
        if (e.neighbors <= params.anisotropyMinNeighbors) {
            // Sphere of kIsolatedSplatScale radii about the particle itself.
            const float a = kIsolatedSplatScale * radius;
            o[0] = positions[i].x;
            o[1] = positions[i].y;
            o[2] = positions[i].z;
            o[3] = a;
            for (int row = 0; row < 3; ++row) o[4 + 4 * row + row] = 1.0f / a;
            continue;
        }
        o[3] = scale * length(e.axes[0]);
        for (int row = 0; row < 3; ++row)
            for (int col = 0; col < 3; ++col)
                o[4 + 4 * row + col] = e.g[std::size_t(3 * row + col)] / scale;
    }
    return out;
}

}  // namespace

struct SceneRenderer::Impl {
    gl::Program sphereShade{
        "spheres", shaders::kSphereVertex,
        fragment({shaders::kColorMap, shaders::kSphereHit, shaders::kSphereShadeMain})};
    gl::Program sphereDepth{"liquid depth", shaders::kSphereVertex,
                            fragment({shaders::kSphereHit, shaders::kSphereDepthMain})};
    gl::Program ellipsoidDepth{"liquid ellipsoid depth", shaders::kEllipsoidVertex,
                               shaders::kEllipsoidDepthFragment};
    gl::Program diffuseShade{"white water", shaders::kSphereVertex,
                             fragment({shaders::kSphereHit, shaders::kDiffuseMain})};
    gl::Program sphereThickness{"liquid thickness", shaders::kSphereVertex,
                                shaders::kThicknessFragment};
    gl::Program skyProgram{"sky", shaders::kFullscreenVertex,
                           fragment({shaders::kSky, shaders::kSkyMain})};
    gl::Program floorProgram{"floor", shaders::kFloorVertex, shaders::kFloorFragment};
    gl::Program lineProgram{"lines", shaders::kFloorVertex, shaders::kLineFragment};
    gl::Program solidProgram{"solids", shaders::kSolidVertex, shaders::kSolidFragment};
    gl::Program smoothing{"depth smoothing", shaders::kFullscreenVertex,
                          fragment({shaders::kSmoothingMain})};
    gl::Program composite{"liquid composite", shaders::kFullscreenVertex,
                          fragment({shaders::kSky, shaders::kCompositeMain})};

    GLuint particleVao = 0, particleVbo = 0;
    GLuint ellipsoidVao = 0, ellipsoidVbo = 0;
    GLuint diffuseVao = 0, diffuseVbo = 0;
    std::size_t diffuseCount = 0;
    // The uploaded particles, kept for the ellipsoids (computed when the
    // liquid look first needs them after an upload).
    std::vector<float> packed;
    bool ellipsoidsCurrent = false;
    GLuint emptyVao = 0;
    GLuint boxVao = 0, boxVbo = 0;
    GLuint floorVao = 0, floorVbo = 0;
    GLuint solidVao = 0, solidVbo = 0;
    std::size_t solidVertices = 0;
    std::size_t count = 0;
    float radius = 0.01f;
    Aabb domain{{0, 0, 0}, {1, 1, 1}};  // in `frame`
    LocalFrame frame;                   // what everything is drawn relative to (setDomain)

    // Liquid look targets, sized to the image.
    int width = 0, height = 0;
    gl::Texture backgroundColor, backgroundDepth, depthA, depthB, thickness, splatDepth;
    gl::Framebuffer backgroundFbo, depthFboA, depthFboB, thicknessFbo;

    Impl() {
        glGenVertexArrays(1, &particleVao);
        glGenBuffers(1, &particleVbo);
        glBindVertexArray(particleVao);
        glBindBuffer(GL_ARRAY_BUFFER, particleVbo);
        glEnableVertexAttribArray(0);
        glVertexAttribPointer(0, 4, GL_FLOAT, GL_FALSE, 4 * sizeof(float), nullptr);
        glVertexAttribDivisor(0, 1);  // one particle per instance
        glGenVertexArrays(1, &diffuseVao);
        glGenBuffers(1, &diffuseVbo);
        glBindVertexArray(diffuseVao);
        glBindBuffer(GL_ARRAY_BUFFER, diffuseVbo);
        glEnableVertexAttribArray(0);
        glVertexAttribPointer(0, 4, GL_FLOAT, GL_FALSE, 4 * sizeof(float), nullptr);
        glVertexAttribDivisor(0, 1);
        glGenVertexArrays(1, &ellipsoidVao);
        glGenBuffers(1, &ellipsoidVbo);
        glBindVertexArray(ellipsoidVao);
        glBindBuffer(GL_ARRAY_BUFFER, ellipsoidVbo);
        for (GLuint k = 0; k < 4; ++k) {
            glEnableVertexAttribArray(k);
            glVertexAttribPointer(
                k, k == 0 ? 4 : 3, GL_FLOAT, GL_FALSE, 16 * sizeof(float),
                reinterpret_cast<const void*>(std::size_t(4 * k) * sizeof(float)));
            glVertexAttribDivisor(k, 1);
        }
        glGenVertexArrays(1, &emptyVao);
        glGenVertexArrays(1, &boxVao);
        glGenBuffers(1, &boxVbo);
        glGenVertexArrays(1, &floorVao);
        glGenBuffers(1, &floorVbo);
        for (const auto& [vao, vbo] : {std::pair{boxVao, boxVbo}, std::pair{floorVao, floorVbo}}) {
            glBindVertexArray(vao);
            glBindBuffer(GL_ARRAY_BUFFER, vbo);
            glEnableVertexAttribArray(0);
            glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 3 * sizeof(float), nullptr);
        }
        // Solids: position and normal per vertex.
        glGenVertexArrays(1, &solidVao);
        glGenBuffers(1, &solidVbo);
        glBindVertexArray(solidVao);
        glBindBuffer(GL_ARRAY_BUFFER, solidVbo);
        glEnableVertexAttribArray(0);
        glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), nullptr);
        glEnableVertexAttribArray(1);
        glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float),
                              reinterpret_cast<const void*>(3 * sizeof(float)));
        glBindVertexArray(0);
        setDomain(domain);
    }

    ~Impl() {
        glDeleteBuffers(1, &particleVbo);
        glDeleteBuffers(1, &ellipsoidVbo);
        glDeleteBuffers(1, &diffuseVbo);
        glDeleteVertexArrays(1, &ellipsoidVao);
        glDeleteVertexArrays(1, &diffuseVao);
        glDeleteBuffers(1, &boxVbo);
        glDeleteBuffers(1, &floorVbo);
        glDeleteBuffers(1, &solidVbo);
        glDeleteVertexArrays(1, &solidVao);
        glDeleteVertexArrays(1, &particleVao);
        glDeleteVertexArrays(1, &emptyVao);
        glDeleteVertexArrays(1, &boxVao);
        glDeleteVertexArrays(1, &floorVao);
    }

    void setDomain(const Aabb& box) {
        domain = box;
        const Vec3 a = box.min, b = box.max;
        const float corners[8][3] = {{a.x, a.y, a.z}, {b.x, a.y, a.z}, {b.x, b.y, a.z},
                                     {a.x, b.y, a.z}, {a.x, a.y, b.z}, {b.x, a.y, b.z},
                                     {b.x, b.y, b.z}, {a.x, b.y, b.z}};
        const int edges[24] = {0, 1, 1, 2, 2, 3, 3, 0, 4, 5, 5, 6,
                               6, 7, 7, 4, 0, 4, 1, 5, 2, 6, 3, 7};
        std::vector<float> lines;
        for (const int e : edges) lines.insert(lines.end(), corners[e], corners[e] + 3);
        glBindBuffer(GL_ARRAY_BUFFER, boxVbo);
        glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(lines.size() * sizeof(float)), lines.data(),
                     GL_STATIC_DRAW);
        // The floor reaches well beyond the domain, just under its bottom.
        const float reach = 3.0f * std::max({box.extent().x, box.extent().y, box.extent().z});
        const float y = a.y - 1e-4f * reach;
        const float cx = 0.5f * (a.x + b.x), cz = 0.5f * (a.z + b.z);
        const float floorQuad[] = {cx - reach, y, cz - reach, cx + reach, y, cz - reach,
                                   cx - reach, y, cz + reach, cx + reach, y, cz + reach};
        glBindBuffer(GL_ARRAY_BUFFER, floorVbo);
        glBufferData(GL_ARRAY_BUFFER, sizeof(floorQuad), floorQuad, GL_STATIC_DRAW);
        glBindBuffer(GL_ARRAY_BUFFER, 0);
    }

    void resize(int w, int h) {
        if (w == width && h == height) return;
        width = w;
        height = h;
        backgroundColor.allocate(GL_RGBA8, GL_RGBA, GL_UNSIGNED_BYTE, w, h, true);
        backgroundDepth.allocate(GL_DEPTH_COMPONENT24, GL_DEPTH_COMPONENT, GL_UNSIGNED_INT, w, h,
                                 false);
        splatDepth.allocate(GL_DEPTH_COMPONENT24, GL_DEPTH_COMPONENT, GL_UNSIGNED_INT, w, h, false);
        depthA.allocate(GL_R32F, GL_RED, GL_FLOAT, w, h, false);
        depthB.allocate(GL_R32F, GL_RED, GL_FLOAT, w, h, false);
        thickness.allocate(GL_R32F, GL_RED, GL_FLOAT, w, h, false);
        backgroundFbo.attach(backgroundColor.id(), backgroundDepth.id());
        depthFboA.attach(depthA.id(), splatDepth.id());
        depthFboB.attach(depthB.id(), 0);
        // The thickness pass is depth-tested (not written) against the
        // background's depth, so water hidden behind a solid adds nothing.
        thicknessFbo.attach(thickness.id(), backgroundDepth.id());
    }

    void drawBackground(const View& v) {
        glDisable(GL_DEPTH_TEST);
        skyProgram.use();
        glUniformMatrix3fv(skyProgram.uniform("uViewToWorld"), 1, GL_FALSE,
                           glm::value_ptr(v.viewToWorld));
        glUniform2fv(skyProgram.uniform("uTanHalf"), 1, glm::value_ptr(v.tanHalf));
        glBindVertexArray(emptyVao);
        glDrawArrays(GL_TRIANGLES, 0, 3);

        glEnable(GL_DEPTH_TEST);
        glDepthFunc(GL_LESS);
        const glm::mat4 viewProj = v.proj * v.view;
        floorProgram.use();
        glUniformMatrix4fv(floorProgram.uniform("uViewProj"), 1, GL_FALSE,
                           glm::value_ptr(viewProj));
        const float size = std::max({domain.extent().x, domain.extent().z});
        glUniform1f(floorProgram.uniform("uTile"), size / 8.0f);
        glUniform2f(floorProgram.uniform("uCenter"), 0.5f * (domain.min.x + domain.max.x),
                    0.5f * (domain.min.z + domain.max.z));
        glUniform1f(floorProgram.uniform("uFade"), 3.0f * size);
        glBindVertexArray(floorVao);
        glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
        drawSolids(v);
    }

    void drawSolids(const View& v) {
        if (solidVertices == 0) return;
        const glm::mat4 viewProj = v.proj * v.view;
        solidProgram.use();
        glUniformMatrix4fv(solidProgram.uniform("uViewProj"), 1, GL_FALSE,
                           glm::value_ptr(viewProj));
        glUniform3fv(solidProgram.uniform("uEye"), 1, glm::value_ptr(v.eye));
        glUniform3fv(solidProgram.uniform("uLightWorld"), 1, glm::value_ptr(v.lightWorld));
        glUniform3f(solidProgram.uniform("uColor"), 0.50f, 0.49f, 0.47f);  // stone grey
        glBindVertexArray(solidVao);
        glDrawArrays(GL_TRIANGLES, 0, GLsizei(solidVertices));
    }

    void drawBox(const View& v) {
        const glm::mat4 viewProj = v.proj * v.view;
        lineProgram.use();
        glUniformMatrix4fv(lineProgram.uniform("uViewProj"), 1, GL_FALSE, glm::value_ptr(viewProj));
        glUniform3f(lineProgram.uniform("uColor"), 0.15f, 0.17f, 0.2f);
        glBindVertexArray(boxVao);
        glDrawArrays(GL_LINES, 0, 24);
    }

    void drawParticles(const gl::Program& program, const View& v, float quadScale = 1.5f,
                       float radiusScale = 1.0f) {
        if (count == 0) return;
        program.use();
        glUniformMatrix4fv(program.uniform("uView"), 1, GL_FALSE, glm::value_ptr(v.view));
        glUniformMatrix4fv(program.uniform("uProj"), 1, GL_FALSE, glm::value_ptr(v.proj));
        glUniform1f(program.uniform("uRadius"), radius * radiusScale);
        glUniform1f(program.uniform("uQuadScale"), quadScale);
        glBindVertexArray(particleVao);
        glDrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, GLsizei(count));  // the one draw call
    }

    // Depth splats as ellipsoids (one instanced draw call).
    void drawEllipsoidDepth(const View& v) {
        if (count == 0) return;
        if (!ellipsoidsCurrent) {
            const std::vector<float> e = splatEllipsoids(packed, radius);
            glBindBuffer(GL_ARRAY_BUFFER, ellipsoidVbo);
            glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(e.size() * sizeof(float)), e.data(),
                         GL_STREAM_DRAW);
            glBindBuffer(GL_ARRAY_BUFFER, 0);
            ellipsoidsCurrent = true;
        }
        ellipsoidDepth.use();
        glUniformMatrix4fv(ellipsoidDepth.uniform("uView"), 1, GL_FALSE, glm::value_ptr(v.view));
        glUniformMatrix4fv(ellipsoidDepth.uniform("uProj"), 1, GL_FALSE, glm::value_ptr(v.proj));
        glBindVertexArray(ellipsoidVao);
        glDrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, GLsizei(count));
    }

    // White water over whatever is in the bound framebuffer's depth buffer;
    // `depthBias` metres towards the camera (see shaders::kDiffuseMain).
    void drawDiffuse(const View& v, float depthBias) {
        if (diffuseCount == 0) return;
        diffuseShade.use();
        glUniformMatrix4fv(diffuseShade.uniform("uView"), 1, GL_FALSE, glm::value_ptr(v.view));
        glUniformMatrix4fv(diffuseShade.uniform("uProj"), 1, GL_FALSE, glm::value_ptr(v.proj));
        glUniform1f(diffuseShade.uniform("uRadius"), radius * kDiffuseRadiusScale);
        glUniform1f(diffuseShade.uniform("uQuadScale"), 1.5f);
        glUniform3fv(diffuseShade.uniform("uLightView"), 1, glm::value_ptr(v.lightView));
        glUniform1f(diffuseShade.uniform("uDepthBias"), depthBias);
        glBindVertexArray(diffuseVao);
        glDrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, GLsizei(diffuseCount));
    }

    void renderSpheres(GLuint target, const View& v, const RenderSettings& s) {
        glBindFramebuffer(GL_FRAMEBUFFER, target);
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        drawBackground(v);
        sphereShade.use();
        glUniform1i(sphereShade.uniform("uColorMode"), int(s.color));
        const float hi = s.rangeMax > s.rangeMin ? s.rangeMax : s.rangeMin + 1e-6f;
        glUniform2f(sphereShade.uniform("uRange"), s.rangeMin, hi);
        glUniform3fv(sphereShade.uniform("uFlatColor"), 1, s.flatColor.data());
        glUniform3fv(sphereShade.uniform("uLightView"), 1, glm::value_ptr(v.lightView));
        drawParticles(sphereShade, v);
        // Foam among the surface particles shows through their spheres.
        if (s.drawDiffuse) drawDiffuse(v, radius);
        if (s.drawBox) drawBox(v);
    }

    void renderLiquid(GLuint target, const View& v, const RenderSettings& s) {
        // Background (sky, floor, solids; the box comes later) into a
        // texture: what the water refracts.
        glBindFramebuffer(GL_FRAMEBUFFER, backgroundFbo.id());
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        drawBackground(v);

        // 1. Depth splats: nearest sphere surface per pixel. The depth buffer
        // starts as the background's, so water behind a solid is not drawn.
        glBindFramebuffer(GL_FRAMEBUFFER, depthFboA.id());
        glClearColor(0.0f, 0.0f, 0.0f, 0.0f);
        glClear(GL_COLOR_BUFFER_BIT);
        glBindFramebuffer(GL_READ_FRAMEBUFFER, backgroundFbo.id());
        glBlitFramebuffer(0, 0, width, height, 0, 0, width, height, GL_DEPTH_BUFFER_BIT,
                          GL_NEAREST);
        glBindFramebuffer(GL_FRAMEBUFFER, depthFboA.id());
        glEnable(GL_DEPTH_TEST);
        glDepthFunc(GL_LESS);
        // Ellipsoids (or spheres) larger than the particles (as in FleX's
        // renderer) close the gaps of a disordered surface before smoothing.
        if (s.anisotropic)
            drawEllipsoidDepth(v);
        else
            drawParticles(sphereDepth, v, 1.5f, kLiquidRadiusScale);

        // 2. Thickness: all spheres in front of the background added up
        // (depth test against the background, no depth writes).
        glBindFramebuffer(GL_FRAMEBUFFER, thicknessFbo.id());
        glClear(GL_COLOR_BUFFER_BIT);
        glDepthMask(GL_FALSE);
        glEnable(GL_BLEND);
        glBlendFunc(GL_ONE, GL_ONE);
        drawParticles(sphereThickness, v, 4.5f);  // the Gaussian's 3 sigma
        glDisable(GL_BLEND);
        glDepthMask(GL_TRUE);
        glDisable(GL_DEPTH_TEST);

        // The box goes into the background after the water's depth tests
        // (its lines must not cut the water's depth).
        if (s.drawBox) {
            glBindFramebuffer(GL_FRAMEBUFFER, backgroundFbo.id());
            glEnable(GL_DEPTH_TEST);
            drawBox(v);
            glDisable(GL_DEPTH_TEST);
        }

        // 3. Depth smoothing; each iteration is two passes, A -> B (horizontal) -> A (vertical).
        smoothing.use();
        glUniform1f(smoothing.uniform("uPixelsPerMetre"), v.pixelsPerMetre);
        glUniform1f(smoothing.uniform("uRadius"), radius * kLiquidRadiusScale);
        glBindVertexArray(emptyVao);
        for (int i = 0; i < s.smoothingIterations; ++i) {
            glBindFramebuffer(GL_FRAMEBUFFER, depthFboB.id());
            gl::bindTexture(smoothing, "uDepth", 0, depthA.id());
            glUniform2i(smoothing.uniform("uStep"), 1, 0);
            glDrawArrays(GL_TRIANGLES, 0, 3);
            glBindFramebuffer(GL_FRAMEBUFFER, depthFboA.id());
            gl::bindTexture(smoothing, "uDepth", 0, depthB.id());
            glUniform2i(smoothing.uniform("uStep"), 0, 1);
            glDrawArrays(GL_TRIANGLES, 0, 3);
        }

        // 4. Composite into the target, writing depth so the box can be drawn on top.
        glBindFramebuffer(GL_FRAMEBUFFER, target);
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        glEnable(GL_DEPTH_TEST);
        glDepthFunc(GL_ALWAYS);
        composite.use();
        gl::bindTexture(composite, "uDepth", 0, depthA.id());
        gl::bindTexture(composite, "uThickness", 1, thickness.id());
        gl::bindTexture(composite, "uBackground", 2, backgroundColor.id());
        gl::bindTexture(composite, "uBackgroundDepth", 3, backgroundDepth.id());
        glUniformMatrix4fv(composite.uniform("uProj"), 1, GL_FALSE, glm::value_ptr(v.proj));
        glUniformMatrix3fv(composite.uniform("uViewToWorld"), 1, GL_FALSE,
                           glm::value_ptr(v.viewToWorld));
        glUniform2fv(composite.uniform("uTanHalf"), 1, glm::value_ptr(v.tanHalf));
        glUniform3fv(composite.uniform("uLightView"), 1, glm::value_ptr(v.lightView));
        // Absorption per metre: red goes first, so thick water turns blue-green.
        glUniform3f(composite.uniform("uAbsorption"), 8.0f, 2.2f, 1.0f);
        glUniform3f(composite.uniform("uScatter"), 0.02f, 0.22f, 0.35f);
        glUniform1f(composite.uniform("uRefraction"), 0.15f);
        glUniform1f(composite.uniform("uMinThickness"), kMinThicknessScale * radius);
        glBindVertexArray(emptyVao);
        glDrawArrays(GL_TRIANGLES, 0, 3);
        glDepthFunc(GL_LESS);
        // White water over the smoothed surface: foam on it and bubbles
        // within two splat radii under it are seen.
        if (s.drawDiffuse) drawDiffuse(v, 2.0f * kLiquidRadiusScale * radius);
        if (s.drawBox) drawBox(v);
        glActiveTexture(GL_TEXTURE0);
    }
};

SceneRenderer::SceneRenderer() : impl_(std::make_unique<Impl>()) {}
SceneRenderer::~SceneRenderer() = default;

// Far from the origin a float's spacing reaches the pixels (1 mm at 10 km)
// and the view matrix loses the scene: everything is drawn relative to the
// World's local frame (pbf/world/local_frame.hpp), which is the world's own
// near the origin.
namespace {

// `world` when the frame is the world's, else a copy in `shifted` whose
// points (x, y, z first in each `stride` floats) are in the frame.
template <class Points>
const Points& inFrame(const Points& world, Points& shifted, std::size_t stride,
                      const LocalFrame& frame) {
    if (!frame.shifted()) return world;
    shifted = world;
    std::vector<float>& data = shifted.data;
    for (std::size_t k = 0; k + 2 < data.size(); k += stride) {
        const Vec3 p = frame.toFrame(Vec3{data[k], data[k + 1], data[k + 2]});
        data[k] = p.x;
        data[k + 1] = p.y;
        data[k + 2] = p.z;
    }
    return shifted;
}

}  // namespace

void SceneRenderer::setDomain(const Aabb& domain) {
    impl_->frame = localFrame(domain);
    impl_->setDomain(impl_->frame.toFrame(domain));
}
void SceneRenderer::setParticleRadius(float radius) {
    impl_->radius = radius;
    impl_->ellipsoidsCurrent = false;
}
void SceneRenderer::setSolids(const SolidMesh& world) {
    SolidMesh shifted;
    const SolidMesh& mesh = inFrame(world, shifted, 6, impl_->frame);
    glBindBuffer(GL_ARRAY_BUFFER, impl_->solidVbo);
    glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(mesh.data.size() * sizeof(float)), mesh.data.data(),
                 GL_STATIC_DRAW);
    glBindBuffer(GL_ARRAY_BUFFER, 0);
    impl_->solidVertices = mesh.data.size() / 6;
}

std::size_t SceneRenderer::particleCount() const {
    return impl_->count;
}

std::size_t SceneRenderer::diffuseCount() const {
    return impl_->diffuseCount;
}

void SceneRenderer::uploadDiffuse(const RenderParticles& world) {
    RenderParticles shifted;
    const RenderParticles& diffuse = inFrame(world, shifted, 4, impl_->frame);
    glBindBuffer(GL_ARRAY_BUFFER, impl_->diffuseVbo);
    glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(diffuse.data.size() * sizeof(float)),
                 diffuse.data.data(), GL_STREAM_DRAW);
    glBindBuffer(GL_ARRAY_BUFFER, 0);
    impl_->diffuseCount = diffuse.count();
}

void SceneRenderer::upload(const RenderParticles& world) {
    RenderParticles shifted;
    const RenderParticles& particles = inFrame(world, shifted, 4, impl_->frame);
    glBindBuffer(GL_ARRAY_BUFFER, impl_->particleVbo);
    glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(particles.data.size() * sizeof(float)),
                 particles.data.data(), GL_STREAM_DRAW);
    glBindBuffer(GL_ARRAY_BUFFER, 0);
    impl_->count = particles.count();
    impl_->packed = particles.data;
    impl_->ellipsoidsCurrent = false;
}

void SceneRenderer::render(unsigned framebuffer, int width, int height, const Camera& world,
                           const RenderSettings& settings) {
    Camera camera = world;
    camera.position = impl_->frame.toFrame(world.position);
    camera.target = impl_->frame.toFrame(world.target);
    const View v = makeView(camera, impl_->domain, width, height);
    glViewport(0, 0, width, height);
    glDisable(GL_BLEND);
    glDisable(GL_CULL_FACE);
    glDisable(GL_SCISSOR_TEST);
    glDepthMask(GL_TRUE);
    glClearColor(0.0f, 0.0f, 0.0f, 1.0f);
    if (settings.style == Style::Liquid) {
        impl_->resize(width, height);
        impl_->renderLiquid(framebuffer, v, settings);
    } else {
        impl_->renderSpheres(framebuffer, v, settings);
    }
    glBindVertexArray(0);
    glUseProgram(0);
}

}  // namespace pbf::render
