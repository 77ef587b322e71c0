// Static solid objects as signed distance fields.
//
// Every solid answers "how far is this point from my surface, and which way
// is out" (negative inside). The solver uses that for three things:
//   * collision: particles are kept at least one particle radius outside
//     every solid, with a sphere-traced sweep so that a particle never
//     crosses a thin wall within one step (continuous collision detection);
//   * boundary density: a solid within the kernel radius contributes the
//     density of the rest lattice continued beyond its surface (the flat-wall
//     table of the domain walls, evaluated at the signed distance), so water
//     at a solid is neither under-dense nor sticky (the role of Akinci et
//     al. 2012's boundary particles, from the SDF instead of samples);
//   * wall response: restitution and friction on contact.
// Analytic shapes (box, sphere, plane, cylinder) are exact; triangle meshes
// are converted to a narrow-band level set with OpenVDB (mesh_solid.cpp).
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "pbf/core/config.hpp"
#include "pbf/core/vec3.hpp"
#include "pbf/geometry/pose.hpp"

namespace pbf {

class BoundaryScale;  // src/geometry/boundary_scale.hpp

// ShapeData's fixed-size part: plain data that a device copies whole (the
// GPU backend's DeviceShape derives from it).
struct ShapeParameters {
    enum class Kind { Box, Sphere, Plane, Cylinder, Samples };
    Kind kind = Kind::Samples;
    Aabb box;             // Box
    Vec3 center;          // Sphere
    float radius = 0.0f;  // Sphere, Cylinder
    Vec3 point, normal;   // Plane (unit normal)
    Vec3 base, axis;      // Cylinder (unit axis)
    float height = 0.0f;  // Cylinder
    // Samples: the value beyond the nodes, and the offset subtracted from
    // the interpolated value (an open mesh's shell half-thickness).
    float outside = 0.0f;
    float offset = 0.0f;
};

// A solid's shape as plain data, in its own frame: what a backend that
// evaluates the shape away from the host objects (the GPU backend,
// src/backend/gpu) needs. Analytic shapes give their parameters (the same
// distance functions then run there, src/geometry/shape_distance.hpp); other
// shapes their distance field sampled on a grid (trilinear in between).
struct ShapeData : ShapeParameters {
    // Samples: signed distances at the nodes origin + (i, j, k) * spacing
    // (i fastest).
    Vec3 origin;
    float spacing = 0.0f;
    int nx = 0, ny = 0, nz = 0;
    std::vector<float> values;
};

class Solid {
  public:
    virtual ~Solid() = default;
    // Signed distance from the surface (metres, negative inside) and the
    // outward unit normal (the normalised gradient of the distance).
    virtual float signedDistance(const Vec3& p, Vec3& normal) const = 0;
    // A box containing the solid's surface in its own frame (infinite planes
    // clip it to the domain).
    virtual Aabb bounds() const = 0;
    virtual std::string describe() const = 0;
    // The shape as plain data (ShapeData). The default samples
    // signedDistance at nodes `spacing` apart over bounds() grown by
    // `margin`; the built-in shapes give their exact parameters, meshes their
    // level set's voxels.
    virtual ShapeData shapeData(float spacing, float margin) const;
};

// Where a solid is and how it moves: the pose of its frame and the velocity
// of that frame (linear velocity of the frame's origin, angular velocity
// about it, world axes). Static solids have zero velocities.
struct SolidMotion {
    Pose pose;
    Vec3 velocity;         // m/s
    Vec3 angularVelocity;  // rad/s

    // Velocity of the solid's material at world point p: v + omega x (p - origin).
    PBF_HD Vec3 velocityAt(const Vec3& p) const {
        return velocity + cross(angularVelocity, p - pose.position);
    }
};

// The solids of a world, each a shape in its own frame placed by a pose.
// Queries return the nearest solid's distance.
//
// A solid may be `coupled` (the surface of a rigid body): the solver then
// records the momentum its boundary gives the fluid, and the World applies
// the reaction to the body (docs/architecture.md, "Rigid bodies").
class SolidSet {
  public:
    void add(std::unique_ptr<Solid> shape, const SolidMotion& motion = {}, bool coupled = false);
    bool empty() const { return shapes_.empty(); }
    std::size_t size() const { return shapes_.size(); }
    const Solid& shape(std::size_t i) const { return *shapes_[i]; }
    const SolidMotion& motion(std::size_t i) const { return motions_[i]; }
    // Moves solid i (between steps); its world bounds follow.
    void setMotion(std::size_t i, const SolidMotion& motion);
    // Whether any solid has a non-zero velocity.
    bool anyMoving() const { return moving_; }
    // Whether solid i feels the fluid (a rigid body's surface), and whether any does.
    bool coupled(std::size_t i) const { return coupled_[i]; }
    bool anyCoupled() const { return anyCoupled_; }
    // A finite body's boundary density relative to the flat wall
    // (src/geometry/boundary_scale.hpp): the factor at world point p, 1 for
    // solids without one (static solids, the domain walls).
    void setBoundaryScale(std::size_t i, std::shared_ptr<const BoundaryScale> scale);
    bool hasBoundaryScale(std::size_t i) const { return scales_[i] != nullptr; }
    float boundaryScale(std::size_t i, const Vec3& p) const;
    // How strongly water wets solid i when surface tension is on: the work
    // of adhesion in units of the water's work of cohesion 2 sigma, [0, 1]
    // (Young-Dupre: contact angle acos(2 a - 1)); 0 by default.
    void setAdhesion(std::size_t i, float adhesion);
    float adhesion(std::size_t i) const { return adhesion_[i]; }
    // The ratio grid itself (null without one), for backends that copy it.
    const BoundaryScale* boundaryScaleGrid(std::size_t i) const { return scales_[i].get(); }
    // Whether solid i's pose is the identity (its shape is queried directly).
    bool identityPose(std::size_t i) const { return identity_[i]; }
    // World-space box around solid i's surface.
    const Aabb& bounds(std::size_t i) const { return bounds_[i]; }

    // Smallest signed distance over the solids whose bounds lie within
    // `reach` of p; returns `reach` (and leaves normal and nearest unset) if
    // none does. `nearest` (may be null) receives the index of that solid.
    float signedDistance(const Vec3& p, float reach, Vec3& normal,
                         std::size_t* nearest = nullptr) const;

    // A uniform grid over `box` listing, per cell, the solids whose bounds
    // come within `margin` of it, so that queries with reach <= margin test
    // a few solids instead of all (a hundred bodies). Queries give the same
    // results with or without it (same candidates, same order). Moving a
    // solid drops the grid until the next call; call it between steps, never
    // while queries run.
    void buildIndex(const Aabb& box, float margin);

    // The signed distance to solid k placed by its pose, its outward normal
    // into `normal` (no reach test).
    float distanceTo(std::size_t k, const Vec3& p, Vec3& normal) const;

  private:
    struct Index {
        bool valid = false;
        Aabb box;
        float margin = 0.0f;
        float inverseCell = 0.0f;
        int nx = 0, ny = 0, nz = 0;
        std::vector<std::uint32_t> start;  // CSR offsets per cell
        std::vector<std::uint32_t> items;  // solid indices, ascending per cell
    };
    Index index_;

    std::vector<std::unique_ptr<Solid>> shapes_;
    std::vector<SolidMotion> motions_;
    std::vector<bool> identity_;  // pose is the identity: query the shape directly
    std::vector<Aabb> bounds_;
    std::vector<bool> coupled_;
    std::vector<std::shared_ptr<const BoundaryScale>> scales_;
    std::vector<float> adhesion_;
    bool moving_ = false;
    bool anyCoupled_ = false;
};

// Placement of a mesh: p' = rotation(p * scale) + translation, rotation as
// Euler angles in degrees about x, then y, then z. The scale is baked into
// the mesh's distance field; rotation and translation are its pose().
struct Transform {
    Vec3 scale{1.0f, 1.0f, 1.0f};
    Vec3 rotationDegrees;
    Vec3 translation;
    Vec3 apply(const Vec3& p) const {
        return pose().toWorld({p.x * scale.x, p.y * scale.y, p.z * scale.z});
    }
    Pose pose() const { return {translation, fromEulerDegrees(rotationDegrees)}; }
};

std::unique_ptr<Solid> makeBoxSolid(const Aabb& box);
std::unique_ptr<Solid> makeSphereSolid(const Vec3& center, float radius);
// Half-space below the plane: solid where dot(p - point, normal) < 0.
std::unique_ptr<Solid> makePlaneSolid(const Vec3& point, const Vec3& normal, const Aabb& domain);
// Capped cylinder from `base` along `axis` (normalised inside) for `height`.
std::unique_ptr<Solid> makeCylinderSolid(const Vec3& base, const Vec3& axis, float radius,
                                         float height);

struct MeshSolidOptions {
    float voxelSize = 0.0f;  // metres; the level set's resolution
    float bandWidth = 0.0f;  // metres on each side of the surface that must be exact
    // Open or non-manifold meshes (boundary edges, edges shared by more than
    // two triangles) have no inside; they become shells of this thickness.
    float shellThickness = 0.0f;
};

struct MeshInfo {
    std::size_t vertices = 0;
    std::size_t triangles = 0;
    std::size_t boundaryEdges = 0;
    std::size_t nonManifoldEdges = 0;
    bool closed() const { return boundaryEdges == 0 && nonManifoldEdges == 0; }
};

// Loads a triangle mesh (OBJ) and builds its signed distance field. Throws
// SolidError naming the file for: missing / unreadable file, no triangles,
// non-finite vertices, more than 10 million triangles, or a level set that
// would need more than `maxVoxels` voxels.
std::unique_ptr<Solid> loadMeshSolid(const std::filesystem::path& file, const Transform& transform,
                                     const MeshSolidOptions& options, MeshInfo* info = nullptr,
                                     double maxVoxels = 2e8);

class SolidError : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

}  // namespace pbf
