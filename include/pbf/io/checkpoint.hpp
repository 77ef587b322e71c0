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
//   u64      FNV-1a 64 hash of the payload
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
// 7: the count of particles outlets removed
inline constexpr std::uint32_t kCheckpointFormatVersion = 7;
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
    std::vector<EmitterState> emitters;  // one per emitter of the scene
    std::vector<RigidBodyState> bodies;  // one per rigid body of the scene
    std::uint64_t removed = 0;           // particles the outlets removed so far
    RunTotals totals;
};

// The world's state (totals left empty), for the scene with this fingerprint.
Checkpoint captureCheckpoint(const World& world, std::uint64_t sceneFingerprint);
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

// Bytes a checkpoint of `particles` particles and `csvBytes` of stats takes.
std::uintmax_t checkpointBytes(std::size_t particles, std::size_t csvBytes);

}  // namespace pbf
