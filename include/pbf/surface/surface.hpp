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
#include <string_view>

#include "pbf/core/vec3.hpp"
#include "pbf/surface/mesh.hpp"

namespace pbf::surface {

// How the particles become a level set (docs/surfaces.md, "Methods").
enum class SurfaceMethod {
    // Union of enlarged spheres, eroded back and smoothed (steps 1-4 above).
    isotropic,
    // Yu & Turk 2013 (anisotropic.hpp): every particle's kernel is an
    // ellipsoid shaped by its neighbourhood, flat at flat water and thin in
    // sheets; the level set is an iso-surface of the summed kernels.
    anisotropic,
};
// "isotropic" / "anisotropic"; parseSurfaceMethod throws std::invalid_argument.
const char* toString(SurfaceMethod method);
SurfaceMethod parseSurfaceMethod(std::string_view text);

struct SurfaceParams {
    float particleRadius = 0.0f;  // r, metres, > 0 (required)
    SurfaceMethod method = SurfaceMethod::anisotropic;
    // Voxel edge of the level set in units of r: (0, 2]. Smaller is finer and
    // slower (cost ~ 1 / voxel^2). Must leave the rasterised spheres at least
    // 1.5 voxels wide.
    float voxelSize = 0.5f;
    // Rasterised sphere radius in units of r before the erosion back to r:
    // [1.5, 4]. Larger closes wider gaps and flattens more (thin sheets and
    // droplet chains merge), smaller keeps more detail.
    float sphereScale = 2.5f;
    // (isotropic) Mean-curvature smoothing iterations after the closing:
    // [0, 100]. The anisotropic method's surface is smooth by construction
    // and takes `anisotropicSmoothing` iterations instead.
    int smoothing = 6;
    // (anisotropic) Yu & Turk 2013's parameters, lengths in units of r
    // (docs/surfaces.md says how the defaults were chosen):
    //  kernelRadius: the isotropic kernel radius h, [2, 8];
    //  neighborRadius: the covariance's neighbourhood, [2, 12];
    //  centreSmoothing: lambda of the smoothed centres (eq. 6), [0, 1];
    //  maxAnisotropy: k_r, the largest ratio of the ellipsoid's axes, [1, 16]
    //    (the paper's 4 meshes one-particle sheets 2.9 r thick; 6 gives 2 r);
    //  isolatedScale: k_n, the kernel scale of particles with few
    //    neighbours, [0.25, 1];
    //  anisotropyMinNeighbors: N_eps, with fewer neighbours the kernel stays
    //    a sphere, [1, 200] (a one-particle sheet has about 25 within 6 r);
    //  anisotropicSmoothing: mean-curvature iterations afterwards, [0, 100].
    // k_s is derived (anisotropic.hpp).
    float kernelRadius = 6.0f;
    float neighborRadius = 6.0f;
    float centreSmoothing = 0.55f;
    float maxAnisotropy = 6.0f;
    float isolatedScale = 0.5f;
    int anisotropyMinNeighbors = 15;
    int anisotropicSmoothing = 1;
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
