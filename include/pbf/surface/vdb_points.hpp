// Particle caches as OpenVDB point data (.vdb), the format Houdini and
// Blender load as point clouds.
//
// One PointDataGrid named "points" with the attributes
//   P (vec3f, position, metres), v (vec3f, velocity, m/s),
//   density (float, kg/m^3), id (int32, the particle's stable id).
// Positions are stored voxel-relative in 32-bit floats (NullCodec): they
// read back equal up to float rounding of (position - voxel centre).
#pragma once

#include <filesystem>

#include "pbf/core/particles.hpp"
#include "pbf/io/io.hpp"

namespace pbf::surface {

// Writes atomically (temporary file + rename). Throws IoError.
void writeParticlesVdb(const std::filesystem::path& path, const ParticleStore& particles);
void writeParticlesVdb(const std::filesystem::path& path, const ParticleFrame& frame);
// Reads a file written by writeParticlesVdb, particles in id order (file
// order if there is no id attribute). Throws IoError naming the file.
ParticleFrame readParticlesVdb(const std::filesystem::path& path);

}  // namespace pbf::surface
