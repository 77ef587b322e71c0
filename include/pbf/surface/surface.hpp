// Particles -> narrow-band level set -> closed triangle mesh (OpenVDB).
//
// The algorithm (docs/surfaces.md):
//  1. Drop stray particles: a particle with fewer than `minNeighbors` others
//     within 4 r (the PBF kernel support) is spray; rasterising it would
//     leave a cloud of tiny blobs.
//  2. Rasterise every remaining particle as a sphere of radius
//     `sphereScale` * r into a narrow-band signed distance field
//     (openvdb::tools::ParticlesToLevelSet, a CSG union of spheres, as in
//     Zhu & Bridson 2005 "Animating sand as a fluid", section 6).
//  3. Erode by about (sphereScale - 1) r: the union of enlarged spheres
//     closes the gaps between neighbours, the erosion puts the surface back
//     at one radius outside the outer particle centres (a morphological
//     closing, which Houdini's "VDB from Particles" + "VDB Reshape SDF" also
//     do). The erosion is the mean sag-corrected height of the union over a
//     flat particle layer minus r, so that flat water keeps its volume.
//  4. Smooth with `smoothing` iterations of mean-curvature flow
//     (openvdb::tools::LevelSetFilter), which flattens the bumps of single
//     spheres and barely moves flat or gently curved water.
//  5. Extract the zero iso-surface with openvdb::tools::volumeToMesh
//     (dual contouring with optional adaptivity).
//
// The OpenVDB grid stays inside LevelSet (pimpl) so that including this
// header does not pull in OpenVDB.
#pragma once

#include <cstddef>
#include <filesystem>
#include <memory>
#include <span>
#include <string>

#include "pbf/surface/mesh.hpp"
#include "pbf/vec3.hpp"

namespace pbf::surface {

struct SurfaceParams {
    float particleRadius = 0.0f;  // r, metres, > 0 (required)
    // Voxel edge of the level set in units of r: (0, 2]. Smaller is finer and
    // slower (cost ~ 1 / voxel^2). Must leave the rasterised spheres at least
    // 1.5 voxels wide.
    float voxelSize = 0.5f;
    // Rasterised sphere radius in units of r before the erosion back to r:
    // [1.5, 4]. Larger closes wider gaps and flattens more (thin sheets and
    // droplet chains merge), smaller keeps more detail.
    float sphereScale = 2.5f;
    // Mean-curvature smoothing iterations after the closing: [0, 100].
    int smoothing = 6;
    // Particles with fewer neighbours within 4 r are spray and not meshed:
    // [0, 1000]; 0 keeps every particle.
    int minNeighbors = 4;
    // volumeToMesh adaptivity: 0 = uniform triangles, up to 1 = fewest
    // triangles on flat parts. [0, 1].
    float adaptivity = 0.0f;
};

// "" when valid, else "field: problem" (field names as on the command line).
std::string validate(const SurfaceParams& params);

class LevelSet {
  public:
    LevelSet();
    ~LevelSet();
    LevelSet(LevelSet&&) noexcept;
    LevelSet& operator=(LevelSet&&) noexcept;

    std::size_t activeVoxels() const;
    bool empty() const;
    struct Impl;
    Impl& impl() { return *impl_; }
    const Impl& impl() const { return *impl_; }

  private:
    std::unique_ptr<Impl> impl_;
};

struct BuildReport {
    std::size_t particles = 0;     // input
    std::size_t sprayDropped = 0;  // fewer than minNeighbors neighbours
};

// Steps 1-4. Throws std::invalid_argument for invalid params. Uses TBB
// (through OpenVDB) for parallelism.
LevelSet buildLevelSet(std::span<const Vec3> positions, const SurfaceParams& params,
                       BuildReport* report = nullptr);
// Step 5: the closed mesh of the zero iso-surface.
TriangleMesh extractMesh(const LevelSet& levelSet, float adaptivity);
// Both in one call.
TriangleMesh reconstructSurface(std::span<const Vec3> positions, const SurfaceParams& params,
                                BuildReport* report = nullptr);

// The level set as an OpenVDB file with one FloatGrid named "surface"
// (class level set; Houdini, Blender "Volume" objects open it). Atomic.
void writeLevelSetVdb(const std::filesystem::path& path, const LevelSet& levelSet);

// Particle radius from the particles alone: half the median distance to the
// nearest neighbour (PBF keeps neighbours about 2 r apart; the median
// ignores spray). Throws std::invalid_argument for fewer than 2 particles.
float estimateParticleRadius(std::span<const Vec3> positions);

}  // namespace pbf::surface
