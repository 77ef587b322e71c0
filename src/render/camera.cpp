#include "pbf/render/camera.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace pbf::render {
namespace {

constexpr float kDegrees = std::numbers::pi_v<float> / 180.0f;

bool finite(const Vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

Vec3 normalized(const Vec3& v) {
    return v * (1.0f / length(v));
}

}  // namespace

std::string validateCamera(const Camera& camera) {
    if (!finite(camera.position)) return "camera.position: must be finite";
    if (!finite(camera.target)) return "camera.target: must be finite";
    if (!(camera.fovY >= 1.0f && camera.fovY <= 170.0f))
        return fmt::format("camera.fov: must be in [1, 170] degrees, got {}", camera.fovY);
    const Vec3 view = camera.target - camera.position;
    const float distance = length(view);
    if (!(distance > 1e-6f)) return "camera.position: must differ from camera.target";
    // The up vector is +y: a view straight up or down has no defined roll.
    if (std::abs(view.y) / distance > 0.9999f)
        return "camera.position: the view direction must not be vertical (up is +y)";
    return {};
}

std::string validateResolution(int width, int height) {
    if (width < kMinImageSide || width > kMaxImageSide)
        return fmt::format("width: must be in [{}, {}], got {}", kMinImageSide, kMaxImageSide,
                           width);
    if (height < kMinImageSide || height > kMaxImageSide)
        return fmt::format("height: must be in [{}, {}], got {}", kMinImageSide, kMaxImageSide,
                           height);
    return {};
}

Camera frameBox(const Aabb& box, float aspect, float fovY) {
    const Vec3 center = (box.min + box.max) * 0.5f;
    const float radius = 0.5f * length(box.extent());
    // The sphere must fit the narrower of the two fields of view.
    const float halfY = 0.5f * fovY * kDegrees;
    const float halfX = std::atan(std::tan(halfY) * aspect);
    const float half = std::min(halfX, halfY);
    const float distance = radius / std::sin(half) * 1.02f;
    // From the front (+z), 25 degrees above and 20 degrees to the right.
    const float pitch = 25.0f * kDegrees;
    const float yaw = 20.0f * kDegrees;
    const Vec3 direction{std::cos(pitch) * std::sin(yaw), std::sin(pitch),
                         std::cos(pitch) * std::cos(yaw)};
    Camera camera;
    camera.target = center;
    camera.position = center + direction * distance;
    camera.fovY = fovY;
    return camera;
}

OrbitCamera::OrbitCamera(const Camera& start) : target_(start.target), fovY_(start.fovY) {
    const Vec3 back = start.position - start.target;
    distance_ = length(back);
    const Vec3 d = normalized(back);
    pitch_ = std::asin(std::clamp(d.y, -1.0f, 1.0f)) / kDegrees;
    yaw_ = std::atan2(d.x, d.z) / kDegrees;
}

void OrbitCamera::orbit(float dYawDegrees, float dPitchDegrees) {
    yaw_ = std::fmod(yaw_ + dYawDegrees, 360.0f);
    pitch_ = std::clamp(pitch_ + dPitchDegrees, -89.0f, 89.0f);
}

void OrbitCamera::pan(float dxFraction, float dyFraction) {
    const Camera c = camera();
    const Vec3 forward = normalized(c.target - c.position);
    const Vec3 right = normalized(cross(forward, Vec3{0.0f, 1.0f, 0.0f}));
    const Vec3 up = cross(right, forward);
    target_ += (right * dxFraction + up * dyFraction) * distance_;
}

void OrbitCamera::zoom(float factor) {
    if (factor > 0.0f) distance_ = std::clamp(distance_ * factor, 1e-3f, 1e4f);
}

Camera OrbitCamera::camera() const {
    const float pitch = pitch_ * kDegrees;
    const float yaw = yaw_ * kDegrees;
    const Vec3 back{std::cos(pitch) * std::sin(yaw), std::sin(pitch),
                    std::cos(pitch) * std::cos(yaw)};
    Camera c;
    c.target = target_;
    c.position = target_ + back * distance_;
    c.fovY = fovY_;
    return c;
}

}  // namespace pbf::render
