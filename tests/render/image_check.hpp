// Checking rendered images against the scene (render tests): where a box
// lands on screen, projected independently of the renderer with GLM, and
// how much two images differ at a pixel.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "pbf/core/vec3.hpp"
#include "pbf/render/camera.hpp"
#include "pbf/render/headless.hpp"

namespace pbf::render::image_check {

// Pixel rectangle [x0, x1) x [y0, y1), top row 0.
struct Rect {
    int x0, y0, x1, y1;
};

// The box's screen rectangle in a width x height image, scaled about its
// centre by `scale` and grown by `margin` pixels.
inline Rect projectBox(const Camera& camera, const Aabb& box, float scale, int margin, int width,
                       int height) {
    const glm::mat4 view = glm::lookAt(
        glm::vec3(camera.position.x, camera.position.y, camera.position.z),
        glm::vec3(camera.target.x, camera.target.y, camera.target.z), glm::vec3(0, 1, 0));
    const glm::mat4 proj =
        glm::perspective(glm::radians(camera.fovY), float(width) / float(height), 0.01f, 100.0f);
    const Vec3 c = (box.min + box.max) * 0.5f;
    const Vec3 half = box.extent() * (0.5f * scale);
    float x0 = 1e9f, y0 = 1e9f, x1 = -1e9f, y1 = -1e9f;
    for (int corner = 0; corner < 8; ++corner) {
        const glm::vec3 p(c.x + ((corner & 1) ? half.x : -half.x),
                          c.y + ((corner & 2) ? half.y : -half.y),
                          c.z + ((corner & 4) ? half.z : -half.z));
        const glm::vec3 s =
            glm::project(p, view, proj, glm::vec4(0, 0, float(width), float(height)));
        x0 = std::min(x0, s.x);
        x1 = std::max(x1, s.x);
        y0 = std::min(y0, float(height) - s.y);
        y1 = std::max(y1, float(height) - s.y);
    }
    return {int(std::floor(x0)) - margin, int(std::floor(y0)) - margin, int(std::ceil(x1)) + margin,
            int(std::ceil(y1)) + margin};
}

// Sum over R, G, B of the absolute difference at pixel (x, y).
inline int difference(const Image& a, const Image& b, int x, int y) {
    const std::size_t i = (std::size_t(y) * std::size_t(a.width) + std::size_t(x)) * 4;
    int d = 0;
    for (int k = 0; k < 3; ++k) d += std::abs(int(a.rgba[i + k]) - int(b.rgba[i + k]));
    return d;
}

}  // namespace pbf::render::image_check
