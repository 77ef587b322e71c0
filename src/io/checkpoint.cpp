#include "pbf/io/checkpoint.hpp"

#include <fmt/format.h>
#include <zlib.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <fstream>
#include <type_traits>

#include "io/binary_stream.hpp"
#include "io/checkpoint_format.hpp"
#include "io/checkpoint_particles.hpp"
#include "pbf/core/version.hpp"
#include "pbf/io/io.hpp"
#include "pbf/world/world.hpp"

namespace pbf {
namespace {

static_assert(std::endian::native == std::endian::little,
              "checkpoints assume a little-endian host");

constexpr char kMagic[8] = {'P', 'B', 'F', 'C', 'K', 'P', 'T', '\n'};
using detail::kHeaderBytes;

using detail::BinaryReader;
using detail::BinaryWriter;
using detail::fail;
using detail::readParticleArrays;
using detail::savedBytesPerParticle;
using detail::writeParticleArrays;

}  // namespace

std::string detail::checkpointPrefix(const Checkpoint& c) {
    BinaryWriter w;
    w.value(c.sceneFingerprint);
    w.string(c.pbfVersion);
    w.value<std::int32_t>(c.frame);
    w.value(c.time);
    w.value<std::uint64_t>(c.particles.nextId());
    return w.bytes();
}

std::string detail::checkpointSuffix(const Checkpoint& c) {
    BinaryWriter w;
    w.array(c.emitters);
    w.array(c.bodies);
    const RunTotals& t = c.totals;
    w.value<std::int64_t>(t.substeps);
    w.value(t.solverMilliseconds);
    w.value(t.wallSeconds);
    w.value(t.densityErrorSum);
    w.value(t.maxDensityError);
    w.value(t.maxEscaped);
    w.value(t.maxInsideSolid);
    w.string(t.statsCsv);
    w.string(t.bodiesCsv);
    w.value(c.removed);
    return w.bytes();
}

namespace {

std::string serialize(const Checkpoint& c) {
    BinaryWriter arrays;
    writeParticleArrays(arrays, c.particles);
    return detail::checkpointPrefix(c) + arrays.bytes() + detail::checkpointSuffix(c);
}

}  // namespace

Checkpoint detail::deserializeCheckpoint(const std::string& payload, const std::string& name) {
    BinaryReader r(payload, name);
    Checkpoint c;
    c.sceneFingerprint = r.value<std::uint64_t>("scene fingerprint");
    c.pbfVersion = r.string("pbf version");
    c.frame = r.value<std::int32_t>("frame");
    c.time = r.value<double>("time");
    ParticleStore& p = c.particles;
    const auto nextId = r.value<std::uint64_t>("next id");
    readParticleArrays(r, p);
    r.array(c.emitters, "emitters");
    r.array(c.bodies, "rigid bodies");
    RunTotals& t = c.totals;
    t.substeps = r.value<std::int64_t>("substeps");
    t.solverMilliseconds = r.value<double>("solver time");
    t.wallSeconds = r.value<double>("wall time");
    t.densityErrorSum = r.value<double>("density error sum");
    t.maxDensityError = r.value<double>("max density error");
    t.maxEscaped = r.value<std::uint64_t>("max escaped");
    t.maxInsideSolid = r.value<std::uint64_t>("max inside solid");
    t.statsCsv = r.string("stats.csv");
    t.bodiesCsv = r.string("bodies.csv");
    c.removed = r.value<std::uint64_t>("removed particles");
    if (!r.atEnd()) fail(name, "corrupt checkpoint: trailing bytes");

    // The checksum passed, so these only fail for a file written by a buggy
    // or foreign program; still, never hand an inconsistent store to the solver.
    if (c.frame < 0 || !std::isfinite(c.time) || c.time < 0.0)
        fail(name, "corrupt checkpoint: bad frame or time");
    std::vector<std::uint64_t> ids = p.id;
    std::sort(ids.begin(), ids.end());
    if (std::adjacent_find(ids.begin(), ids.end()) != ids.end() ||
        (!ids.empty() && ids.back() >= nextId))
        fail(name, "corrupt checkpoint: particle ids are not unique or exceed the next id");
    p.predicted = p.position;  // the working copies start from the state
    p.setNextId(nextId);
    return c;
}

Checkpoint captureCheckpoint(const World& world, std::uint64_t sceneFingerprint, bool ownPart) {
    WorldState state = world.captureState(ownPart);
    Checkpoint c;
    c.sceneFingerprint = sceneFingerprint;
    c.pbfVersion = kVersion;
    c.frame = state.frame;
    c.time = state.time;
    c.particles = std::move(state.particles);
    c.first = state.first;
    c.total = state.total;
    c.emitters = std::move(state.emitters);
    c.bodies = std::move(state.bodies);
    c.removed = state.removed;
    return c;
}

void restoreCheckpoint(const Checkpoint& c, World& world, std::uint64_t sceneFingerprint,
                       const std::string& name) {
    if (c.pbfVersion != kVersion)
        fail(name,
             fmt::format(
                 "checkpoint written by pbf {}, this is pbf {}: solvers of different versions "
                 "give different results; start the run again without --resume",
                 c.pbfVersion, kVersion));
    if (c.sceneFingerprint != sceneFingerprint)
        fail(name,
             fmt::format(
                 "checkpoint belongs to a different scene (fingerprint {:016x}, this scene and "
                 "its --set overrides give {:016x}): resume with the same scene and the same "
                 "overrides, or start again without --resume",
                 c.sceneFingerprint, sceneFingerprint));
    if (c.emitters.size() != world.emitters().size())
        fail(name, fmt::format("corrupt checkpoint: {} emitter states for a scene with {} emitters",
                               c.emitters.size(), world.emitters().size()));
    if (c.bodies.size() != world.bodyCount())
        fail(name,
             fmt::format("corrupt checkpoint: {} rigid body states for a scene with {} bodies",
                         c.bodies.size(), world.bodyCount()));
    WorldState state;
    state.particles = c.particles;
    state.particles.predicted = state.particles.position;
    state.first = c.first;
    state.total = c.total;
    state.emitters = c.emitters;
    state.bodies = c.bodies;
    state.removed = c.removed;
    state.frame = c.frame;
    state.time = c.time;
    world.restoreState(std::move(state));
}

std::string detail::checkpointHeader(std::uint64_t payloadBytes, std::uint64_t checksum) {
    std::string header(kMagic, sizeof(kMagic));
    const std::uint32_t version = kCheckpointFormatVersion, reserved = 0;
    header.append(reinterpret_cast<const char*>(&version), 4);
    header.append(reinterpret_cast<const char*>(&reserved), 4);
    header.append(reinterpret_cast<const char*>(&payloadBytes), 8);
    header.append(reinterpret_cast<const char*>(&checksum), 8);
    return header;
}

std::uint64_t detail::checksum(const void* data, std::uint64_t bytes, std::uint64_t crc) {
    // zlib's crc32 takes 32-bit lengths: in pieces.
    const auto* at = static_cast<const Bytef*>(data);
    for (std::uint64_t done = 0; done < bytes;) {
        const auto n = static_cast<uInt>(std::min<std::uint64_t>(bytes - done, 1u << 30));
        crc = ::crc32(uLong(crc), at + done, n);
        done += n;
    }
    return crc;
}

std::uint64_t detail::combineChecksums(std::uint64_t first, std::uint64_t second,
                                       std::uint64_t secondBytes) {
    return ::crc32_combine(uLong(first), uLong(second), z_off_t(secondBytes));
}

void writeCheckpoint(const std::filesystem::path& path, const Checkpoint& checkpoint) {
    const std::string payload = serialize(checkpoint);
    const std::string header =
        detail::checkpointHeader(payload.size(), detail::checksum(payload.data(), payload.size()));
    writeFileAtomically(path, [&](std::ostream& out) {
        out.write(header.data(), static_cast<std::streamsize>(header.size()));
        out.write(payload.data(), static_cast<std::streamsize>(payload.size()));
    });
}

detail::CheckpointHeader detail::readCheckpointHeader(std::istream& in, const std::string& name) {
    char header[kHeaderBytes];
    if (!in.read(header, sizeof(header)))
        fail(name, "not a pbf checkpoint (shorter than the checkpoint header)");
    if (std::memcmp(header, kMagic, sizeof(kMagic)) != 0)
        fail(name, "not a pbf checkpoint (bad magic)");
    std::uint32_t version = 0;
    std::uint64_t size = 0, hash = 0;
    std::memcpy(&version, header + 8, 4);
    std::memcpy(&size, header + 16, 8);
    std::memcpy(&hash, header + 24, 8);
    if (version < kCheckpointFormatVersion)
        fail(name, fmt::format("checkpoint format version {} was written by an older pbf (this "
                               "pbf reads version {}: 64-bit particle ids since version 5, "
                               "positions in the world's local frame since 6, outlets' counts "
                               "since 7, a checksum that ranks compute in parts since 8); its "
                               "run cannot "
                               "be resumed: start it again without --resume",
                               version, kCheckpointFormatVersion));
    if (version != kCheckpointFormatVersion)
        fail(name, fmt::format(
                       "checkpoint format version {} is not supported (this pbf reads version {})",
                       version, kCheckpointFormatVersion));
    // Compare the declared size with what the stream holds before allocating.
    const auto start = in.tellg();
    in.seekg(0, std::ios::end);
    const auto end = in.tellg();
    in.seekg(start);
    if (start < 0 || end < start) fail(name, "cannot determine the checkpoint's size");
    const auto available = static_cast<std::uint64_t>(end - start);
    if (size != available)
        fail(name,
             fmt::format("checkpoint is truncated or has trailing data ({} payload bytes declared, "
                         "{} present)",
                         size, available));
    return {size, hash};
}

Checkpoint readCheckpoint(std::istream& in, const std::string& name) {
    const auto [size, hash] = detail::readCheckpointHeader(in, name);
    std::string payload(static_cast<std::size_t>(size), '\0');
    if (!in.read(payload.data(), static_cast<std::streamsize>(size)))
        fail(name, "cannot read the checkpoint");
    if (detail::checksum(payload.data(), payload.size()) != hash)
        fail(name, "checkpoint is corrupt (checksum mismatch)");
    return detail::deserializeCheckpoint(payload, name);
}

Checkpoint readCheckpoint(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) fail(path.string(), "cannot open checkpoint");
    return readCheckpoint(in, path.string());
}

std::uintmax_t checkpointBytes(std::size_t particles, std::size_t csvBytes) {
    // Header, scalars and length prefixes (< 512 bytes), the particle
    // arrays (optional fields counted as on: the most a checkpoint holds), the CSVs.
    return kHeaderBytes + 512 + std::uintmax_t{particles} * detail::savedBytesPerParticle() +
           csvBytes;
}

}  // namespace pbf
