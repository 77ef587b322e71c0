// The anisotropic method's level set (private header of pbf_surface;
// includes OpenVDB).
#pragma once

#include <openvdb/openvdb.h>

#include <span>

#include "pbf/surface/surface.hpp"

namespace pbf::surface::detail {

// The iso-surface of the Yu & Turk field of `positions` (anisotropic.hpp)
// as a narrow-band level set of `halfWidth` voxels of edge `voxel` metres.
openvdb::FloatGrid::Ptr anisotropicLevelSet(std::span<const Vec3> positions,
                                            const SurfaceParams& params, double voxel,
                                            float halfWidth);

}  // namespace pbf::surface::detail
