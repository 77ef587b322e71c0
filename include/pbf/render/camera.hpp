// Cameras for the viewer and the headless renderer.
//
// A Camera is a plain look-at description (position, target, vertical field
// of view); validateCamera() reports a clear error instead of clamping, so
// that `pbf render --fov 0` fails with a message rather than a black image.
// OrbitCamera is the viewer's interactive camera: yaw / pitch / distance
// around a target, converted to a Camera every frame.
#pragma once

#include <string>

#include "pbf/core/vec3.hpp"

namespace pbf::render {

struct Camera {
    Vec3 position{0.5f, 0.5f, 2.0f};  // metres
    Vec3 target{0.5f, 0.5f, 0.5f};    // metres
    float fovY = 45.0f;  // vertical field of view, degrees, (0, 180) exclusive; [1, 170] accepted
};

// Empty when valid, else "field: problem" (fov outside [1, 170], position == target,
// non-finite coordinates, or a view direction parallel to the up axis +y).
std::string validateCamera(const Camera& camera);

// Image sizes accepted by the renderer and the viewer: [16, 8192] per side.
inline constexpr int kMinImageSide = 16;
inline constexpr int kMaxImageSide = 8192;
std::string validateResolution(int width, int height);

// A camera that sees the whole box from the front, slightly from above
// (the view of the README images): the box's bounding sphere fits the
// vertical field of view at the given aspect ratio.
Camera frameBox(const Aabb& box, float aspect, float fovY = 40.0f);

// Interactive orbit camera: left drag orbits, right / middle drag pans,
// the wheel zooms (the viewer maps mouse input to these calls).
class OrbitCamera {
  public:
    OrbitCamera() = default;
    explicit OrbitCamera(const Camera& start);

    void orbit(float dYawDegrees, float dPitchDegrees);
    // Moves the target in the view plane by a fraction of the distance.
    void pan(float dxFraction, float dyFraction);
    // Multiplies the distance to the target by `factor` (> 0).
    void zoom(float factor);

    Camera camera() const;
    float fovY() const { return fovY_; }

  private:
    Vec3 target_{0.5f, 0.5f, 0.5f};
    float distance_ = 2.0f;
    float yaw_ = 0.0f;    // degrees about +y, 0 = looking along -z
    float pitch_ = 0.0f;  // degrees, positive = looking down
    float fovY_ = 45.0f;
};

}  // namespace pbf::render
