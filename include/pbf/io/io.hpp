// Files pbf writes and reads.
//
// Every file is written whole: to a temporary file beside the target, then
// renamed over it, so a killed run never leaves a half-written frame.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <istream>
#include <ostream>
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
    std::vector<std::uint32_t> id;
};

// Binary little-endian PLY, one vertex per particle with the properties
// x y z vx vy vz density (float) and id (uint), in id order. Blender,
// Houdini, MeshLab and ParaView open it.
void writeParticlesPly(const std::filesystem::path& path, const ParticleStore& particles);
// Reads a file written by writeParticlesPly (or any binary little-endian
// PLY with float x, y, z; other properties optional). Throws IoError.
ParticleFrame readParticlesPly(const std::filesystem::path& path);
// The same from a stream (must be seekable); `name` is used in error messages.
ParticleFrame readParticlesPly(std::istream& in, const std::string& name);

}  // namespace pbf
