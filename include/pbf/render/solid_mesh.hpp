// The scene's static solids as triangles for the renderer: boxes (12
// triangles), UV spheres, capped cylinders, planes clipped to the domain box
// and OBJ meshes (pbf::loadTriangleMesh, placed by the scene's transform as
// the solver places them).
#pragma once

#include <cstddef>
#include <vector>

#include "pbf/geometry/pose.hpp"
#include "pbf/io/scene.hpp"
#include "pbf/world/world.hpp"

namespace pbf::render {

// Unindexed triangles, 6 floats per vertex (position x, y, z, normal x, y, z),
// 3 vertices per triangle. Normals point out of the solid (the renderer
// lights both sides anyway).
struct SolidMesh {
    std::vector<float> data;
    std::size_t triangleCount() const { return data.size() / 18; }
    Vec3 position(std::size_t vertex) const {
        return {data[6 * vertex], data[6 * vertex + 1], data[6 * vertex + 2]};
    }
};

// Appends one solid's surface to `mesh`. Planes are cut to `domain`.
// Throws pbf::SolidError for a mesh file that cannot be loaded.
void appendSolid(SolidMesh& mesh, const SolidDescription& solid, const Aabb& domain);

// The scene's static solids (those without a `motion`); a mesh that cannot be
// loaded throws pbf::SceneError naming the scene file and the field
// ("scenes/x.json: solids[0].file: ...").
SolidMesh tessellateSolids(const Scene& scene);

// A solid with a prescribed motion: its surface in the shape's own frame and
// what places it at a time (pbf/geometry/prescribed_motion.hpp), in world
// coordinates as the scene gives them.
struct DrivenShape {
    SolidMesh mesh;
    PrescribedMotion motion;
    Pose rest;  // identity for analytic shapes, a mesh's transform
    Vec3 pivot;
};
std::vector<DrivenShape> tessellateDrivenSolids(const Scene& scene);
// Appends every driven solid where its motion puts it at `time` s.
void appendDriven(SolidMesh& out, const std::vector<DrivenShape>& driven, double time);

// The scene's rigid bodies, one mesh each, in their shapes' own frames (a
// box or sphere centred at the origin, a cylinder along y centred at the
// origin, a mesh as its file gives it, scaled): what World::solids()
// places with the pose of the body's solid (World::bodyInfos()[i].solid).
std::vector<SolidMesh> tessellateBodyShapes(const Scene& scene);
// Appends `shape` placed by `pose` to `out`.
void appendPosed(SolidMesh& out, const SolidMesh& shape, const Pose& pose);
// The static solids, every body at its current pose in `world` and every
// driven solid at the world's time.
SolidMesh posedSolids(const SolidMesh& statics, const std::vector<SolidMesh>& bodyShapes,
                      const std::vector<DrivenShape>& driven, const World& world);

}  // namespace pbf::render
