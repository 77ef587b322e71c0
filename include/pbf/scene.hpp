// Scene files: JSON documents that describe a whole simulation.
//
// The format (every field, unit, default and range) is documented in
// docs/scenes.md. Loading is strict: unknown keys, wrong types, out-of-range
// values, empty or overlapping fluid blocks are errors that name the file and
// the field, e.g. "scenes/x.json: solver.iterations: must be in [1, 100], got 0".
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "pbf/params.hpp"
#include "pbf/particles.hpp"

namespace pbf {

class SceneError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// A box of water filled with particles on a cubic lattice of spacing 2 r.
struct FluidBlock {
    Aabb box;
    Vec3 velocity;  // initial velocity, m/s
};

struct OutputParams {
    float fps = 30.0f;          // frames per simulated second, (0, 10000]
    int frames = 90;            // frames to simulate, [1, 1e6]
    std::string directory;      // default "out/<scene name>"
    bool writeParticles = true; // binary PLY per frame
    // Checkpoints for --resume (docs/reliability.md): one is written when
    // `checkpointEvery` frames or `checkpointSeconds` of wall time have passed
    // since the last one (0 turns that trigger off), and at the end of a run.
    int checkpointEvery = 10;          // frames, [0, 1e6]
    float checkpointSeconds = 60.0f;   // wall-clock seconds, [0, 1e6]
    // State guard (include/pbf/state_guard.hpp): the run stops when a particle
    // is faster than max_speed (m/s) or, when max_speed is 0, than
    // max_speed_factor times the free-fall speed over the domain diagonal.
    float maxSpeed = 0.0f;             // m/s, [0, 1e6]; 0: automatic
    float maxSpeedFactor = 10.0f;      // [1, 1e4]
};

struct Scene {
    std::string name;          // from the file name unless given
    std::string source;        // file the scene came from (for messages)
    SimulationParams simulation;
    std::vector<FluidBlock> fluidBlocks;
    OutputParams output;
    // Hash of the scene document after overrides, without the output fields
    // that do not change the simulated states (frames, directory, particles,
    // checkpoint and speed-limit settings): a checkpoint records it so that a
    // run is only resumed with the scene it was started with.
    std::uint64_t fingerprint = 0;
};

// A command-line override "path=value": path is dot-separated
// ("solver.iterations"), value is JSON ("8", "[0,-9.81,0]") or a bare string.
struct SceneOverride {
    std::string path;
    std::string value;
};
SceneOverride parseOverride(std::string_view assignment);  // throws SceneError

Scene loadScene(const std::filesystem::path& file, const std::vector<SceneOverride>& overrides = {});
Scene parseScene(std::string_view jsonText, const std::string& sourceName,
                 const std::vector<SceneOverride>& overrides = {});

// Number of particles the scene's fluid blocks create.
std::size_t countParticles(const Scene& scene);
// Fills the fluid blocks with particles (lattice of spacing 2 r, ids in block order).
ParticleStore createParticles(const Scene& scene);

// Refuses scenes whose particles would not fit in `availableBytes` of memory
// (the bytes per particle the solver needs times the count); throws SceneError.
void checkMemory(const Scene& scene, std::size_t availableBytes);
std::size_t estimatedBytesPerParticle(const SimulationParams& params);

}  // namespace pbf
