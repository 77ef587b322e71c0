// Draws particles with OpenGL 3.3 core: the library behind `pbf view` and
// `pbf render`. Needs a current GL 3.3 core context (a GLFW window or the
// headless EGL context of headless.hpp); libpbf itself has no GL dependency.
//
// Two looks:
//  * Spheres: every particle is a ray-cast sphere impostor on a camera-facing
//    quad, all particles in ONE instanced draw call, coloured by speed,
//    density or a flat colour.
//  * Liquid: screen-space fluid rendering (van der Laan, Green & Sainz 2009,
//    "Screen Space Fluid Rendering with Curvature Flow", I3D): sphere depth
//    splats, a narrow-range filter on the depth, additive thickness, then a
//    composite with normals from the smoothed depth, Fresnel reflection of
//    the sky, and refraction of the background attenuated by the thickness
//    (Beer-Lambert). The depth splats are the particles' anisotropic
//    ellipsoids (Yu & Turk 2013), so flat water and thin streams stay smooth.
//    Algorithm notes in docs/rendering.md.
// Both looks draw white water (pbf foam's spray, foam and bubbles) on request.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "pbf/core/params.hpp"
#include "pbf/core/particles.hpp"
#include "pbf/io/io.hpp"
#include "pbf/render/camera.hpp"

namespace pbf::render {

struct SolidMesh;  // solid_mesh.hpp

enum class Style { Spheres, Liquid };
enum class ColorMode { Speed, Density, Flat };

// "spheres" / "liquid"; "speed" / "density" / "flat". Throw std::invalid_argument otherwise.
Style parseStyle(const std::string& name);
ColorMode parseColorMode(const std::string& name);
const char* toString(Style style);
const char* toString(ColorMode mode);

struct RenderSettings {
    Style style = Style::Spheres;
    ColorMode color = ColorMode::Speed;
    // Values mapped to the two ends of the colour map (m/s or kg/m^3).
    float rangeMin = 0.0f;
    float rangeMax = 1.0f;
    std::array<float, 3> flatColor{0.25f, 0.5f, 0.95f};
    bool drawBox = true;
    // Liquid look: depth smoothing iterations (each a horizontal and a vertical pass), [0, 10].
    int smoothingIterations = 3;
    // Liquid look: depth splats are the particles' anisotropic ellipsoids
    // (Yu & Turk 2013, surface::computeEllipsoids) rather than spheres.
    bool anisotropic = true;
    // White water (uploadDiffuse) drawn, in both looks.
    bool drawDiffuse = true;
};

// The colour map's range that suits a scene: speed from 0 to the free-fall
// speed over the domain height sqrt(2 g H); density rho0 +- 5 %.
void setDefaultRange(RenderSettings& settings, const SimulationParams& params);

// Particle data as the GPU takes it: x, y, z and the colour value per particle.
struct RenderParticles {
    std::vector<float> data;  // 4 floats per particle
    std::size_t count() const { return data.size() / 4; }
};
RenderParticles packParticles(const ParticleStore& particles, ColorMode mode);
RenderParticles packParticles(const ParticleFrame& frame, ColorMode mode);
// Diffuse (white water) particles: x, y, z and the type (0 spray, 1 foam, 2 bubble).
RenderParticles packDiffuse(std::span<const Vec3> positions, std::span<const std::uint8_t> types);

// The colour map (a perceptually ordered blue-cyan-yellow-red ramp) at t in [0, 1];
// the same polynomial as in the shaders, for colour bars drawn on the CPU side.
std::array<float, 3> colorMap(float t);

class SceneRenderer {
  public:
    // Compiles the shaders; throws std::runtime_error with the GL log on failure.
    SceneRenderer();
    ~SceneRenderer();
    SceneRenderer(const SceneRenderer&) = delete;
    SceneRenderer& operator=(const SceneRenderer&) = delete;

    void setDomain(const Aabb& domain);
    void setParticleRadius(float radius);
    // The scene's static solids (tessellateSolids), drawn lit in both looks
    // and, in the liquid look, part of the background the water refracts.
    void setSolids(const SolidMesh& mesh);
    void upload(const RenderParticles& particles);
    std::size_t particleCount() const;
    // White water: pbf foam's diffuse particles (packDiffuse), drawn as small
    // white spheres over the water in both looks. Empty: none.
    void uploadDiffuse(const RenderParticles& diffuse);
    std::size_t diffuseCount() const;

    // Renders into `framebuffer` (0: the window) at width x height pixels.
    void render(unsigned framebuffer, int width, int height, const Camera& camera,
                const RenderSettings& settings);

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace pbf::render
