// CPU side of the renderer: names of styles and colour modes, particle
// packing, the colour map, default colour ranges.
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "pbf/render/renderer.hpp"

namespace pbf::render {

Style parseStyle(const std::string& name) {
    if (name == "spheres") return Style::Spheres;
    if (name == "liquid") return Style::Liquid;
    throw std::invalid_argument("style: must be spheres or liquid, got '" + name + "'");
}

ColorMode parseColorMode(const std::string& name) {
    if (name == "speed") return ColorMode::Speed;
    if (name == "density") return ColorMode::Density;
    if (name == "flat") return ColorMode::Flat;
    throw std::invalid_argument("color: must be speed, density or flat, got '" + name + "'");
}

const char* toString(Style style) {
    return style == Style::Liquid ? "liquid" : "spheres";
}

const char* toString(ColorMode mode) {
    switch (mode) {
        case ColorMode::Speed:
            return "speed";
        case ColorMode::Density:
            return "density";
        case ColorMode::Flat:
            return "flat";
    }
    return "speed";
}

void setDefaultRange(RenderSettings& settings, const SimulationParams& params) {
    if (settings.color == ColorMode::Density) {
        settings.rangeMin = 0.95f * params.fluid.restDensity;
        settings.rangeMax = 1.05f * params.fluid.restDensity;
        return;
    }
    // A particle falling the whole domain height reaches sqrt(2 g H).
    const float g = length(params.gravity);
    const float height = params.domain.extent().y;
    settings.rangeMin = 0.0f;
    settings.rangeMax = std::max(0.1f, std::sqrt(2.0f * g * height));
}

RenderParticles packParticles(const ParticleStore& particles, ColorMode mode) {
    RenderParticles out;
    const std::size_t n = particles.size();
    out.data.resize(4 * n);
    for (std::size_t i = 0; i < n; ++i) {
        out.data[4 * i + 0] = particles.position.x[i];
        out.data[4 * i + 1] = particles.position.y[i];
        out.data[4 * i + 2] = particles.position.z[i];
        out.data[4 * i + 3] =
            mode == ColorMode::Density ? particles.density[i] : length(particles.velocity.get(i));
    }
    return out;
}

RenderParticles packParticles(const ParticleFrame& frame, ColorMode mode) {
    RenderParticles out;
    const std::size_t n = frame.position.size();
    out.data.resize(4 * n);
    for (std::size_t i = 0; i < n; ++i) {
        out.data[4 * i + 0] = frame.position[i].x;
        out.data[4 * i + 1] = frame.position[i].y;
        out.data[4 * i + 2] = frame.position[i].z;
        float value = 0.0f;
        if (mode == ColorMode::Density && i < frame.density.size()) value = frame.density[i];
        if (mode == ColorMode::Speed && i < frame.velocity.size())
            value = length(frame.velocity[i]);
        out.data[4 * i + 3] = value;
    }
    return out;
}

RenderParticles packDiffuse(std::span<const Vec3> positions, std::span<const std::uint8_t> types) {
    if (positions.size() != types.size())
        throw std::invalid_argument("packDiffuse: positions and types differ in length");
    RenderParticles out;
    out.data.resize(4 * positions.size());
    for (std::size_t i = 0; i < positions.size(); ++i) {
        out.data[4 * i + 0] = positions[i].x;
        out.data[4 * i + 1] = positions[i].y;
        out.data[4 * i + 2] = positions[i].z;
        out.data[4 * i + 3] = float(types[i]);
    }
    return out;
}

std::array<float, 3> colorMap(float t) {
    // Keep in step with shaders::kColorMap.
    constexpr float stops[4][3] = {
        {0.05f, 0.20f, 0.70f}, {0.10f, 0.70f, 0.90f}, {0.95f, 0.90f, 0.25f}, {0.85f, 0.15f, 0.10f}};
    t = std::clamp(t, 0.0f, 1.0f);
    const int segment = std::min(2, static_cast<int>(t * 3.0f));
    const float f = t * 3.0f - float(segment);
    std::array<float, 3> c{};
    for (int k = 0; k < 3; ++k)
        c[k] = stops[segment][k] + (stops[segment + 1][k] - stops[segment][k]) * f;
    return c;
}

}  // namespace pbf::render
