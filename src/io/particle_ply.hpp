// The particle PLY frame's layout, shared by the one-process writer
// (src/io/ply.cpp) and the ranks' collective one (src/io/ply_ranks.cpp), so
// both write the same bytes (private header).
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>

#include "pbf/io/io.hpp"

namespace pbf::detail {

inline constexpr const char* kParticlePlyComment = "written by pbf";
inline constexpr PlyProperty kParticlePlyProperties[] = {
    {"float", "x"},  {"float", "y"},  {"float", "z"},       {"float", "vx"},
    {"float", "vy"}, {"float", "vz"}, {"float", "density"}, {"uint", "id"}};

// One vertex of a particle frame, as stored in the file.
struct ParticlePlyRecord {
    float values[7];  // x y z vx vy vz density
    std::uint32_t id;
};
static_assert(sizeof(ParticlePlyRecord) == 32, "a particle PLY vertex is 32 bytes");

// Particle i of `p` as a vertex; an id past 32 bits throws IoError naming `path`.
ParticlePlyRecord particlePlyRecord(const ParticleStore& p, std::size_t i,
                                    const std::filesystem::path& path);
// The header of a binary little-endian vertex PLY with `count` vertices.
std::string plyHeader(std::string_view comment, std::span<const PlyProperty> properties,
                      std::uint64_t count);

}  // namespace pbf::detail
