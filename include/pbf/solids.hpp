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

#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "pbf/vec3.hpp"

namespace pbf {

class Solid {
  public:
    virtual ~Solid() = default;
    // Signed distance from the surface (metres, negative inside) and the
    // outward unit normal (the normalised gradient of the distance).
    virtual float signedDistance(const Vec3& p, Vec3& normal) const = 0;
    // A box containing the solid's surface (infinite planes clip it to the domain).
    virtual Aabb bounds() const = 0;
    virtual std::string describe() const = 0;
};

// The solids of a scene. Queries return the nearest solid's distance.
class SolidSet {
  public:
    void add(std::unique_ptr<Solid> solid);
    bool empty() const { return solids_.empty(); }
    std::size_t size() const { return solids_.size(); }
    const Solid& operator[](std::size_t i) const { return *solids_[i]; }

    // Smallest signed distance over the solids whose bounds lie within
    // `reach` of p; returns `reach` (and leaves normal unset) if none does.
    float signedDistance(const Vec3& p, float reach, Vec3& normal) const;

  private:
    std::vector<std::unique_ptr<Solid>> solids_;
    std::vector<Aabb> bounds_;
};

// Placement of a mesh: p' = rotation(p * scale) + translation, rotation as
// Euler angles in degrees about x, then y, then z.
struct Transform {
    Vec3 scale{1.0f, 1.0f, 1.0f};
    Vec3 rotationDegrees;
    Vec3 translation;
    Vec3 apply(const Vec3& p) const;
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
