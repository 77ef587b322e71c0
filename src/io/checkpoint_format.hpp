// The checkpoint file's pieces (private header), shared by the one-process
// reader and writer (checkpoint.cpp) and the ranks' (checkpoint_ranks.cpp):
//   header   kHeaderBytes: magic, version, payload bytes, checksum
//   payload  prefix (scene fingerprint, version, frame, time, next id),
//            the particle arrays (checkpoint_particles.hpp), suffix (emitters,
//            bodies, the run's totals, removed particles)
#pragma once

#include <cstddef>
#include <cstdint>
#include <istream>
#include <string>

#include "pbf/io/checkpoint.hpp"

namespace pbf::detail {

inline constexpr std::size_t kHeaderBytes = 8 + 4 + 4 + 8 + 8;

std::string checkpointPrefix(const Checkpoint& c);
std::string checkpointSuffix(const Checkpoint& c);
std::string checkpointHeader(std::uint64_t payloadBytes, std::uint64_t checksum);

struct CheckpointHeader {
    std::uint64_t payloadBytes = 0;
    std::uint64_t checksum = 0;
};
// Reads and checks the header (magic, version, the payload's size against
// what the stream holds). Throws IoError naming `name`.
CheckpointHeader readCheckpointHeader(std::istream& in, const std::string& name);
// The payload's fields (checked: ids unique and below the next id).
Checkpoint deserializeCheckpoint(const std::string& payload, const std::string& name);

// CRC-32 (zlib) of `bytes` continuing `crc`; and the CRC of A then B from
// theirs (B of `secondBytes` bytes), so that parts can be summed anywhere.
std::uint64_t checksum(const void* data, std::uint64_t bytes, std::uint64_t crc = 0);
std::uint64_t combineChecksums(std::uint64_t first, std::uint64_t second,
                               std::uint64_t secondBytes);

}  // namespace pbf::detail
