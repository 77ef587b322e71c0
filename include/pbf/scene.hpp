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
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "pbf/params.hpp"
#include "pbf/particles.hpp"
#include "pbf/solids.hpp"

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

// A static solid object (docs/scenes.md, "solids").
struct SolidDescription {
    enum class Kind { Box, Sphere, Plane, Cylinder, Mesh };
    Kind kind = Kind::Box;
    Aabb box;                     // box
    Vec3 center;                  // sphere
    float radius = 0.0f;          // sphere, cylinder
    Vec3 point, normal{0, 1, 0};  // plane
    Vec3 base, axis{0, 1, 0};     // cylinder
    float height = 0.0f;          // cylinder
    std::string file;             // mesh: path resolved against the scene file's folder
    Transform transform;          // mesh
    std::string field;            // "solids[2]", for messages
};

// A nozzle pouring water: discs of particles (lattice spacing 2 r, within
// `radius` of the axis) leave `position` along `direction` at `speed`, one
// disc per 2 r travelled, between `start` and `end` seconds or until
// `maxParticles` have been emitted.
struct EmitterDescription {
    Vec3 position;
    Vec3 direction{0, -1, 0};
    float radius = 0.05f;          // m
    float speed = 1.0f;            // m/s
    float start = 0.0f;            // s
    float end = 1e30f;             // s
    std::size_t maxParticles = 0;  // 0: no budget, only the time window
    std::string field;
};

struct OutputParams {
    float fps = 30.0f;            // frames per simulated second, (0, 10000]
    int frames = 90;              // frames to simulate, [1, 1e6]
    std::string directory;        // default "out/<scene name>"
    bool writeParticles = true;   // binary PLY per frame
    bool writeVdbPoints = false;  // OpenVDB points per frame (frame_NNNNN.vdb, pbf_surface)
    // Checkpoints for --resume (docs/reliability.md): one is written when
    // `checkpointEvery` frames or `checkpointSeconds` of wall time have passed
    // since the last one (0 turns that trigger off), and at the end of a run.
    int checkpointEvery = 10;         // frames, [0, 1e6]
    float checkpointSeconds = 60.0f;  // wall-clock seconds, [0, 1e6]
    // State guard (include/pbf/state_guard.hpp): the run stops when a particle
    // is faster than max_speed (m/s) or, when max_speed is 0, than
    // max_speed_factor times the free-fall speed over the domain diagonal.
    float maxSpeed = 0.0f;         // m/s, [0, 1e6]; 0: automatic
    float maxSpeedFactor = 10.0f;  // [1, 1e4]
};

struct Scene {
    std::string name;    // from the file name unless given
    std::string source;  // file the scene came from (for messages)
    SimulationParams simulation;
    std::vector<FluidBlock> fluidBlocks;
    std::vector<SolidDescription> solids;
    std::vector<EmitterDescription> emitters;
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

Scene loadScene(const std::filesystem::path& file,
                const std::vector<SceneOverride>& overrides = {});
Scene parseScene(std::string_view jsonText, const std::string& sourceName,
                 const std::vector<SceneOverride>& overrides = {});

// Number of particles the scene's fluid blocks create (before solids remove any)
// plus every emitter's budget.
std::size_t countParticles(const Scene& scene);
// Builds the scene's solids (loads meshes); throws SceneError naming the file and field.
std::shared_ptr<const SolidSet> buildSolids(const Scene& scene);
// Fills the fluid blocks with particles (lattice of spacing 2 r, ids in block
// order), leaving out lattice sites closer than one radius to a solid; their
// number goes to `skipped` if given.
ParticleStore createParticles(const Scene& scene, const SolidSet* solids = nullptr,
                              std::size_t* skipped = nullptr);

// Particles in one emitted disc, and the most an emitter emits in the run.
std::size_t emitterDiscSize(const Scene& scene, const EmitterDescription& emitter);
std::size_t emitterBudget(const Scene& scene, const EmitterDescription& emitter);

// Refuses scenes whose particles would not fit in `availableBytes` of memory
// (the bytes per particle the solver needs times the count); throws SceneError.
void checkMemory(const Scene& scene, std::size_t availableBytes);
std::size_t estimatedBytesPerParticle(const SimulationParams& params);

}  // namespace pbf
