// Checkpoints: the complete state of a `pbf run`, so that a killed run can be
// resumed (`pbf run --resume`) and produce frames bit-identical to a run
// that was never interrupted.
//
// What bit-identity needs: the solver sorts particles by grid cell with a
// stable counting sort every step, so the next memory order depends on the
// current one. A checkpoint therefore stores the particle arrays in memory
// order (position, velocity, density, id, the warm start's solve
// acceleration; the predicted positions equal the positions between steps),
// the store's next id, the frame counter and the time, and the rigid bodies'
// states (poses, velocities; the contact solver is rebuilt from them at
// every frame, see src/bodies/contact_world.hpp). It also stores the run's
// totals, the stats.csv and bodies.csv rows so far, the
// scene fingerprint (a resume with another scene is refused) and the pbf
// version (solvers of different versions give different bits).
//
// File format (little-endian), version kCheckpointFormatVersion:
//   8 bytes  magic "PBFCKPT\n"
//   u32      format version
//   u32      0 (reserved)
//   u64      payload size in bytes
//   u64      CRC-32 of the payload (zlib's crc32; the ranks of a distributed
//            run compute it in parts and combine them, crc32_combine)
//   payload  fields in the order of Checkpoint below; strings and arrays are
//            prefixed with their u64 length
// A truncated, corrupt or foreign file is refused with an IoError naming it.
#pragma once

#include <cstdint>
#include <filesystem>
#include <istream>
#include <string>

#include "pbf/bodies/rigid_body.hpp"
#include "pbf/core/particles.hpp"
#include "pbf/world/emitter.hpp"

namespace pbf {

class World;

// 2: emitters, inside_solid; 3: rigid bodies and bodies.csv; 4: warm start;
// 5: 64-bit particle ids and next id; 6: positions in the World's local
// frame (pbf/world/local_frame.hpp; older versions are refused by name);
// 7: the count of particles outlets removed; 8: the CRC-32 checksum in place
// of FNV-1a (written by all ranks at once: checkpoint_ranks)
inline constexpr std::uint32_t kCheckpointFormatVersion = 8;
inline constexpr const char* kCheckpointFileName = "checkpoint.pbfck";

// Totals of a run so far (what runScene needs to continue its summary and
// its stats.csv).
struct RunTotals {
    long long substeps = 0;
    double solverMilliseconds = 0.0;
    double wallSeconds = 0.0;
    double densityErrorSum = 0.0;  // sum over frames of the average density error
    double maxDensityError = 0.0;
    std::uint64_t maxEscaped = 0;
    std::uint64_t maxInsideSolid = 0;
    std::string statsCsv;   // stats.csv so far, header included
    std::string bodiesCsv;  // bodies.csv so far (empty without rigid bodies)
};

struct Checkpoint {
    std::uint64_t sceneFingerprint = 0;
    std::string pbfVersion;
    int frame = 0;
    double time = 0.0;
    ParticleStore particles;             // memory order; `predicted` is not stored
    // A distributed rank's part (captureCheckpoint(..., true),
    // readCheckpointFromRanks): `particles` are the places [first, first +
    // size) of all `total`. total 0: `particles` are all of them.
    std::uint64_t first = 0;
    std::uint64_t total = 0;
    std::vector<EmitterState> emitters;  // one per emitter of the scene
    std::vector<RigidBodyState> bodies;  // one per rigid body of the scene
    std::uint64_t removed = 0;           // particles the outlets removed so far
    RunTotals totals;
};

// The world's state (totals left empty), for the scene with this fingerprint;
// ownPart: a distributed rank's part of the particles (collective).
Checkpoint captureCheckpoint(const World& world, std::uint64_t sceneFingerprint,
                             bool ownPart = false);
// Puts a checkpoint's state into `world`. Throws IoError when the checkpoint
// was written for another scene (fingerprint) or by another pbf version;
// `name` (the file) is used in the messages.
void restoreCheckpoint(const Checkpoint& checkpoint, World& world, std::uint64_t sceneFingerprint,
                       const std::string& name);

// Writes atomically (pbf::writeFileAtomically). Throws IoError.
void writeCheckpoint(const std::filesystem::path& path, const Checkpoint& checkpoint);
// Throws IoError naming the file for missing, truncated, corrupt or foreign files.
Checkpoint readCheckpoint(const std::filesystem::path& path);
// Reads a checkpoint from a stream; `name` is used in error messages.
Checkpoint readCheckpoint(std::istream& in, const std::string& name);

// The same file written by all ranks of a distributed run at once
// (collective, pbf/core/distributed.hpp): each rank gives its part of the
// particles (captureCheckpoint(..., true)) and writes it into the arrays
// with MPI-IO; rank 0 writes the rest from its `checkpoint` and the
// checksum the ranks' parts combine to. The bytes are those writeCheckpoint
// writes for all the particles. One process: writeCheckpoint. Throws
// IoError on every rank.
void writeCheckpointFromRanks(const std::filesystem::path& path, const Checkpoint& checkpoint);
// Reads a checkpoint on all ranks at once (collective): rank r gets the
// places [r N / R, (r + 1) N / R) of the N particles (first, total set),
// every rank the rest; the checksum is checked over the whole file. Any
// rank count reads any file. Throws IoError on every rank. One process:
// readCheckpoint.
Checkpoint readCheckpointFromRanks(const std::filesystem::path& path);

// Bytes a checkpoint of `particles` particles and `csvBytes` of stats takes.
std::uintmax_t checkpointBytes(std::size_t particles, std::size_t csvBytes);

}  // namespace pbf
