// Files pbf writes and reads.
//
// Every file is written whole: to a temporary file beside the target, then
// renamed over it, so a killed run never leaves a half-written frame.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <istream>
#include <ostream>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "pbf/core/particles.hpp"

namespace pbf {

class IoError : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

// Writes `path` atomically: `write` fills a stream on a temporary file that
// is flushed, synced and renamed over `path`. Throws IoError naming the path.
void writeFileAtomically(const std::filesystem::path& path,
                         const std::function<void(std::ostream&)>& write);

// Appends `text` to `path` (created if missing) in one write, so a killed
// run leaves whole lines (stats.csv grows by one row per frame instead of
// being rewritten). Throws IoError naming the path.
void appendToFile(const std::filesystem::path& path, std::string_view text);

// One particle frame as read back from a file.
struct ParticleFrame {
    std::vector<Vec3> position;
    std::vector<Vec3> velocity;
    std::vector<float> density;
    std::vector<std::uint64_t> id;
};

// One property of a PLY vertex: its type ("float", "uint" or "uchar") and name.
struct PlyProperty {
    std::string_view type;
    std::string_view name;
};

// A binary little-endian PLY of `count` vertices with these properties, in
// this order, written atomically: fill(k, record) writes vertex k's values
// packed in property order (4 bytes for float and uint, 1 for uchar) into
// `record`. `comment` names the writer. The one PLY writer of pbf
// (particles here, white water in pbf_surface). Throws IoError.
void writeVertexPly(const std::filesystem::path& path, std::string_view comment,
                    std::span<const PlyProperty> properties, std::size_t count,
                    const std::function<void(std::size_t k, char* record)>& fill);

// A particle id as the PLY files' `uint id` property (32 bits; PLY has no
// 64-bit integer type). Ids are 64-bit; one that does not fit (a run that
// created more than 2^32 particles) throws IoError naming `path` and the
// outputs that keep the whole id (VTK, USD, checkpoints).
std::uint32_t plyId(std::uint64_t id, const std::filesystem::path& path);

// Binary little-endian PLY, one vertex per particle with the properties
// x y z vx vy vz density (float) and id (uint), in id order. Blender,
// Houdini, MeshLab and ParaView open it. An id past 32 bits throws IoError
// (plyId) and leaves no file.
void writeParticlesPly(const std::filesystem::path& path, const ParticleStore& particles);
// The same file written by all ranks of a distributed run at once
// (collective; pbf/core/distributed.hpp): `own` holds this rank's particles,
// in any order. Each rank sends its particles to the rank that holds their
// range of ids, and the ranks write their sorted runs into one file with
// MPI-IO at offsets from the ranks' counts: no rank holds more than about its
// share, and the bytes equal writeParticlesPly's for all the particles. The
// directory must be one that every rank sees. Throws IoError on every rank.
// One process: writeParticlesPly.
void writeParticlesPlyFromRanks(const std::filesystem::path& path, const ParticleStore& own);
// Reads a file written by writeParticlesPly (or any binary little-endian
// PLY with float x, y, z; other properties optional). Throws IoError.
ParticleFrame readParticlesPly(const std::filesystem::path& path);
// The same from a stream (must be seekable); `name` is used in error messages.
ParticleFrame readParticlesPly(std::istream& in, const std::string& name);

}  // namespace pbf
