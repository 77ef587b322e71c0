// The definition of a simulation: plain data with documented defaults, in
// the spirit of Box2D's b2WorldDef. Build one in code (fluid blocks, solids,
// emitters, parameters) or load a scene file (pbf::loadScene gives a Scene,
// a WorldDef with output settings), then construct a pbf::World from it.
// The definition is immutable once the World exists; what may change while
// it runs (iterations, CFL, viscosity, ...) are the World's live settings.
//
// Units are SI (metres, seconds, kilograms); every field's range is in
// docs/scenes.md. validate() reports the first invalid field by the name it
// has in scene files.
#pragma once

#include <cstddef>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "pbf/backend/backend.hpp"
#include "pbf/bodies/rigid_body.hpp"
#include "pbf/core/errors.hpp"
#include "pbf/core/outlet_region.hpp"
#include "pbf/core/params.hpp"
#include "pbf/core/particles.hpp"
#include "pbf/core/vec3.hpp"
#include "pbf/geometry/pose.hpp"
#include "pbf/geometry/solid_description.hpp"
#include "pbf/geometry/solids.hpp"
#include "pbf/world/local_frame.hpp"

namespace pbf {

// A box of water filled with particles on a cubic lattice of spacing 2 r.
struct FluidBlock {
    Aabb box;
    Vec3 velocity;  // initial velocity, m/s
};

// A nozzle pouring water: discs of particles (lattice spacing 2 r, within
// `radius` of the axis) leave `position` along `direction` at `speed`, one
// disc per 2 r travelled, between `start` and `end` seconds or until
// `maxParticles` have been emitted.
struct EmitterDescription {
    Vec3 position;
    Vec3 direction{0, -1, 0};
    float radius = 0.05f;          // m, [particle radius, domain size]
    // A rectangular nozzle (an inlet filling a channel's cross-section)
    // when both are > 0, instead of the disc of `radius`: `width` across the
    // stream and level, `height` across it in the stream's vertical plane
    // (for a vertical stream: along x and z). m, [2 r, domain size].
    float width = 0.0f;
    float height = 0.0f;
    float speed = 1.0f;  // m/s, (0, 100]
    // m^3/s; > 0: the speed is set so that the nozzle's particles carry
    // this volume per second (each 8 r^3), instead of `speed`.
    float flowRate = 0.0f;
    float start = 0.0f;            // s, >= 0
    float end = 1e30f;             // s, > start
    std::size_t maxParticles = 0;  // 0: no budget, only the time window
    std::string field;             // "emitters[0]", for messages
};

// An outlet: water that reaches the region (a box, or the side of a plane
// its normal points to) leaves the simulation at the end of the substep
// (pbf/core/outlet_region.hpp): the end of a channel, a drain.
struct OutletDescription {
    OutletRegion region;
    std::string field;  // "outlets[0]", for messages
};

// The state guard (include/pbf/core/state_guard.hpp): a frame fails when a
// particle is faster than max_speed (m/s) or, when max_speed is 0, than
// max_speed_factor times the free-fall speed over the domain diagonal.
struct GuardParams {
    float maxSpeed = 0.0f;         // m/s, [0, 1e6]; 0: automatic
    float maxSpeedFactor = 10.0f;  // [1, 1e4]
};

struct WorldDef {
    std::string name = "world";
    // Domain, gravity, particle radius, fluid and solver parameters. The
    // fluid and solver fields (and gravity) are the initial live settings.
    SimulationParams simulation;
    std::vector<FluidBlock> fluidBlocks;
    std::vector<SolidDescription> solids;
    std::vector<RigidBodyDescription> rigidBodies;
    std::vector<EmitterDescription> emitters;
    std::vector<OutletDescription> outlets;
    float fps = 30.0f;  // frames per simulated second: World::stepFrame advances 1 / fps, (0, 1e4]
    GuardParams guard;
    std::string source;  // the file it came from (for messages); empty when built in code
};

// Empty when valid, else "field: problem" for the first invalid field
// (field names as in scene files, e.g. "fluid_blocks[1].min").
std::string validate(const WorldDef& def);

// Number of particles the fluid blocks create (before solids remove any).
// Throws SceneError when `processes` equal shares exceed the 32-bit
// particle index of one process.
std::size_t countParticles(const WorldDef& def, int processes = 1);

// The point a solid's prescribed rotations turn about unless its motion
// names a pivot: a box's or a cylinder's centre, a sphere's centre, a
// plane's point, a mesh's translation.
Vec3 pivotOf(const SolidDescription& solid);

// Builds the solids (loads meshes), each placed by its pose. Throws
// SceneError naming the file and field for a broken mesh.
std::unique_ptr<SolidSet> buildSolids(const WorldDef& def);
// Fills the fluid blocks with particles (lattice of spacing 2 r, ids in block
// order), leaving out lattice sites closer than one radius to a solid; their
// number goes to `skipped` if given. `def` is in world coordinates; the
// particles (and `solids`) are in `frame`.
ParticleStore createParticles(const WorldDef& def, const SolidSet* solids = nullptr,
                              std::size_t* skipped = nullptr, const LocalFrame& frame = {});
// The same for the lattice sites [siteBegin, siteEnd) of that order (block,
// then z, y, x rows; countParticles(def) sites in all): a distributed start,
// where each process creates its own range. Its ids start at 0: the process
// adds the particles the ranges before it created.
ParticleStore createParticles(const WorldDef& def, const SolidSet* solids, std::size_t* skipped,
                              const LocalFrame& frame, std::uint64_t siteBegin,
                              std::uint64_t siteEnd);

// Refuses definitions whose particles would not fit in `availableBytes` of
// memory (the bytes per particle the solver needs times the count); throws
// SceneError naming the fluid blocks. Distributed: `processesHere` of the
// run's `processes` share this machine's memory, each holding its share.
void checkMemory(const WorldDef& def, std::size_t availableBytes, int processes = 1,
                 int processesHere = 1);
// The same for the GPU backend on `device` (include/pbf/backend/backend.hpp:
// deviceBytesPerParticle, the cell table), with `availableBytes` free on it;
// the message names the device (`description`, e.g. the GPU's name).
void checkDeviceMemory(const WorldDef& def, BackendKind device, const std::string& description,
                       std::size_t availableBytes);
// Memory the machine can give now (MemAvailable), bytes; 0 when unknown.
std::size_t availableMemoryBytes();
// The most memory this process has held resident so far, bytes.
std::size_t peakResidentBytes();
std::size_t estimatedBytesPerParticle(const SimulationParams& params);

// The speed limit of a world, m/s: guard.max_speed when set (> 0), else
// guard.max_speed_factor * v_ref with v_ref = sqrt(2 |g| D) + the fastest
// initial block velocity, D the domain diagonal: a particle falling freely
// across the whole domain reaches sqrt(2 |g| D), so anything many times
// faster is a blow-up. Without gravity and initial motion, v_ref is the speed
// that crosses the domain in one frame.
double speedLimit(const WorldDef& def);

}  // namespace pbf
