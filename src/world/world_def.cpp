// Validation of a world definition and what is built from it: the solids and
// the fluid blocks' particles.
#include "pbf/world/world_def.hpp"

#include <fmt/format.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>
#include <utility>

#include "pbf/world/emitter.hpp"

namespace pbf {
namespace {

// Particles along one axis of a block from lo to hi: lattice cells of edge
// `spacing` that fit. The block's corners are floats: far from the origin
// they are rounded by up to half their spacing (31 um at 1 km), so a block
// written as 0.3 m wide may be stored a few ulps short of it and would lose
// a row; the rounding of both corners is allowed for. Capped so that absurd
// sizes stay representable and are refused later.
long long latticeCount(float lo, float hi, float spacing) {
    const auto ulp = [](float v) {
        const float a = std::fabs(v);
        return double(std::nextafter(a, std::numeric_limits<float>::infinity()) - a);
    };
    const double slack = 1e-4 + (ulp(lo) + ulp(hi)) / spacing;
    return static_cast<long long>(
        std::min(1e12, std::floor((double(hi) - double(lo)) / spacing + slack)));
}
long long latticeCount(const Aabb& box, int axis, float spacing) {
    return latticeCount(box.min[axis], box.max[axis], spacing);
}

bool overlaps(const Aabb& a, const Aabb& b) {
    return a.min.x < b.max.x && b.min.x < a.max.x && a.min.y < b.max.y && b.min.y < a.max.y &&
           a.min.z < b.max.z && b.min.z < a.max.z;
}

bool positiveBox(const Aabb& box) {
    const Vec3 e = box.extent();
    return e.x > 0 && e.y > 0 && e.z > 0;
}

bool finite(const Vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

std::string fieldOf(const std::string& given, const char* list, std::size_t i) {
    return given.empty() ? fmt::format("{}[{}]", list, i) : given;
}

std::string validateBlocks(const WorldDef& def) {
    const SimulationParams& sim = def.simulation;
    const float spacing = sim.particleSpacing();
    if (def.fluidBlocks.empty() && def.emitters.empty())
        return "fluid_blocks: at least one fluid block (or an emitter) is required";
    for (std::size_t i = 0; i < def.fluidBlocks.size(); ++i) {
        const FluidBlock& block = def.fluidBlocks[i];
        const std::string field = fmt::format("fluid_blocks[{}]", i);
        if (!finite(block.box.min)) return field + ".min: must be finite";
        if (!finite(block.box.max)) return field + ".max: must be finite";
        if (!positiveBox(block.box)) return field + ".max: must be greater than min on every axis";
        if (!finite(block.velocity)) return field + ".velocity: must be finite";
        const Aabb& d = sim.domain;
        if (!d.contains(block.box.min) || !d.contains(block.box.max))
            return field + ".min: the block must lie inside the domain";
        if (latticeCount(block.box, 0, spacing) < 1 || latticeCount(block.box, 1, spacing) < 1 ||
            latticeCount(block.box, 2, spacing) < 1)
            return field +
                   ".max: the block is empty: every side must be at least one particle "
                   "spacing (2 r = " +
                   std::to_string(spacing) + " m) long";
        for (std::size_t k = 0; k < i; ++k)
            if (overlaps(block.box, def.fluidBlocks[k].box))
                return field + ".min: overlaps fluid_blocks[" + std::to_string(k) + "]";
    }
    return {};
}

// The shape of a solid or a rigid body; `field` is how messages name it.
std::string validateShape(const SolidDescription& d, const std::string& field) {
    using Kind = SolidDescription::Kind;
    switch (d.kind) {
        case Kind::Box:
            if (!finite(d.box.min) || !finite(d.box.max) || !positiveBox(d.box))
                return field + ".max: must be greater than min on every axis";
            break;
        case Kind::Sphere:
            if (!finite(d.center)) return field + ".center: must be finite";
            if (!(d.radius > 0.0f) || !std::isfinite(d.radius))
                return field + ".radius: must be positive";
            break;
        case Kind::Plane:
            if (!finite(d.point)) return field + ".point: must be finite";
            if (!(length(d.normal) > 0.0f) || !finite(d.normal))
                return field + ".normal: must be a non-zero vector";
            break;
        case Kind::Cylinder:
            if (!finite(d.base)) return field + ".base: must be finite";
            if (!(length(d.axis) > 0.0f) || !finite(d.axis))
                return field + ".axis: must be a non-zero vector";
            if (!(d.radius > 0.0f) || !std::isfinite(d.radius))
                return field + ".radius: must be positive";
            if (!(d.height > 0.0f) || !std::isfinite(d.height))
                return field + ".height: must be positive";
            break;
        case Kind::Mesh: {
            if (d.file.empty()) return field + ".file: missing (required): path of an OBJ file";
            const Vec3& s = d.transform.scale;
            if (!(s.x > 0 && s.y > 0 && s.z > 0) || !finite(s))
                return field + ".scale: must be positive";
            break;
        }
    }
    if (!(d.adhesion >= 0.0f && d.adhesion <= 1.0f))
        return field + ".adhesion: must be in [0, 1], got " + std::to_string(d.adhesion);
    if (!finite(d.transform.rotationDegrees)) return field + ".rotation: must be finite";
    if (!finite(d.transform.translation)) return field + ".translation: must be finite";
    return validate(d.motion, field + ".motion");
}

std::string validateSolids(const WorldDef& def) {
    for (std::size_t i = 0; i < def.solids.size(); ++i)
        if (std::string problem =
                validateShape(def.solids[i], fieldOf(def.solids[i].field, "solids", i));
            !problem.empty())
            return problem;
    return {};
}

std::string validateRigidBodies(const WorldDef& def) {
    for (std::size_t i = 0; i < def.rigidBodies.size(); ++i) {
        const RigidBodyDescription& b = def.rigidBodies[i];
        const std::string field = fieldOf(b.field, "rigid_bodies", i);
        if (b.shape.kind == SolidDescription::Kind::Plane)
            return field + ".type: a plane cannot be a rigid body (it has no finite mass)";
        if (b.shape.motion.moves())
            return field +
                   ".motion: a rigid body moves by its forces; give the motion to a solid instead";
        if (std::string problem = validateShape(b.shape, field); !problem.empty()) return problem;
        const bool hasDensity = b.density != 0.0f, hasMass = b.mass != 0.0f;
        if (hasDensity == hasMass)
            return field + ".density: give exactly one of density (kg/m^3) and mass (kg)";
        if (hasDensity && !(b.density > 0.0f && b.density <= 1e5f))
            return field + ".density: must be in (0, 100000] kg/m^3, got " +
                   std::to_string(b.density);
        if (hasMass && !(b.mass > 0.0f && b.mass <= 1e9f))
            return field + ".mass: must be in (0, 1e9] kg, got " + std::to_string(b.mass);
        if (!finite(b.velocity)) return field + ".velocity: must be finite";
        if (!finite(b.angularVelocity)) return field + ".angular_velocity: must be finite";
        if (!(b.friction >= 0.0f && b.friction <= 10.0f))
            return field + ".friction: must be in [0, 10], got " + std::to_string(b.friction);
        if (!(b.restitution >= 0.0f && b.restitution <= 1.0f))
            return field + ".restitution: must be in [0, 1], got " + std::to_string(b.restitution);
    }
    return {};
}

std::string validateEmitters(const WorldDef& def) {
    const SimulationParams& sim = def.simulation;
    for (std::size_t i = 0; i < def.emitters.size(); ++i) {
        const EmitterDescription& e = def.emitters[i];
        const std::string field = fieldOf(e.field, "emitters", i);
        if (!sim.domain.contains(e.position))
            return field + ".position: must lie inside the domain";
        if (!(length(e.direction) > 0.0f) || !finite(e.direction))
            return field + ".direction: must be a non-zero vector";
        const Vec3 extent = sim.domain.extent();
        const float size = std::max(extent.x, std::max(extent.y, extent.z));
        if (e.width > 0.0f || e.height > 0.0f) {
            for (const auto& [name, value] : {std::pair{"width", e.width}, {"height", e.height}}) {
                if (!(value >= sim.particleSpacing()))
                    return fmt::format("{}.{}: must be at least the particle spacing {} m", field,
                                       name, sim.particleSpacing());
                if (value > size)
                    return fmt::format("{}.{}: must not exceed the domain's size", field, name);
            }
        } else {
            if (!(e.radius > 0.0f)) return field + ".radius: must be positive";
            if (e.radius < sim.particleRadius)
                return field + ".radius: must be at least the particle radius";
            if (e.radius > size) return field + ".radius: must not exceed the domain's size";
        }
        if (!(e.flowRate >= 0.0f) || !std::isfinite(e.flowRate))
            return field + ".flow_rate: must be positive";
        const float speed = e.flowRate > 0.0f ? flowSpeed(e, sim.particleRadius) : e.speed;
        const char* speedField = e.flowRate > 0.0f ? "flow_rate" : "speed";
        if (!(speed > 0.0f)) return field + "." + speedField + ": must be positive";
        if (speed > 100.0f)
            return fmt::format("{}.{}: the stream would be {:.4g} m/s, more than 100 m/s", field,
                               speedField, speed);
        if (!(e.start >= 0.0f)) return field + ".start: must be >= 0 s";
        if (!(e.end > e.start)) return field + ".end: must be later than start";
    }
    return {};
}

// Whether every corner of `box` (so all of it) is inside the outlet.
bool covers(const OutletRegion& outlet, const Aabb& box) {
    for (int corner = 0; corner < 8; ++corner)
        if (!outlet.contains({corner & 1 ? box.max.x : box.min.x,
                              corner & 2 ? box.max.y : box.min.y,
                              corner & 4 ? box.max.z : box.min.z}))
            return false;
    return true;
}

std::string validateOutlets(const WorldDef& def) {
    const Aabb& domain = def.simulation.domain;
    for (std::size_t i = 0; i < def.outlets.size(); ++i) {
        const OutletRegion& o = def.outlets[i].region;
        const std::string field = fieldOf(def.outlets[i].field, "outlets", i);
        if (o.kind == OutletRegion::Kind::Box) {
            if (!finite(o.box.min)) return field + ".min: must be finite";
            if (!finite(o.box.max)) return field + ".max: must be finite";
            if (!positiveBox(o.box)) return field + ".max: must be greater than min on every axis";
            if (!overlaps(o.box, domain))
                return field + ".min: the outlet must overlap the domain (no water could reach it)";
        } else {
            if (!finite(o.point)) return field + ".point: must be finite";
            if (!finite(o.normal) || !(std::fabs(length(o.normal) - 1.0f) < 1e-3f))
                return field + ".normal: must be a non-zero vector";
            OutletRegion inside = o;  // the domain's side that stays
            inside.normal = -1.0f * o.normal;
            if (covers(inside, domain))
                return field +
                       ".point: the plane leaves the whole domain outside the outlet "
                       "(no water could reach it)";
        }
        if (covers(o, domain))
            return field +
                   ": the outlet covers the whole domain (every particle would leave "
                   "at the first step)";
        for (std::size_t b = 0; b < def.fluidBlocks.size(); ++b)
            if (covers(o, def.fluidBlocks[b].box))
                return fmt::format(
                    "{}: the outlet covers all of fluid_blocks[{}] (its water would leave at "
                    "the first step)",
                    field, b);
        for (std::size_t e = 0; e < def.emitters.size(); ++e)
            if (o.contains(def.emitters[e].position))
                return fmt::format(
                    "{}: the outlet contains the nozzle of emitters[{}] (its water would leave "
                    "as it is emitted)",
                    field, e);
    }
    return {};
}

}  // namespace

std::string validate(const WorldDef& def) {
    if (def.name.empty() || def.name.find('/') != std::string::npos)
        return "name: must be a non-empty name without '/'";
    if (std::string problem = validate(def.simulation); !problem.empty()) return problem;
    if (!(def.fps > 0.0f && def.fps <= 10000.0f)) return "output.fps: must be in (0, 10000]";
    if (!(def.guard.maxSpeed >= 0.0f && def.guard.maxSpeed <= 1e6f))
        return "guard.max_speed: must be in [0, 1000000] m/s (0: automatic)";
    if (!(def.guard.maxSpeedFactor >= 1.0f && def.guard.maxSpeedFactor <= 1e4f))
        return "guard.max_speed_factor: must be in [1, 10000]";
    if (std::string problem = validateBlocks(def); !problem.empty()) return problem;
    if (std::string problem = validateSolids(def); !problem.empty()) return problem;
    if (std::string problem = validateRigidBodies(def); !problem.empty()) return problem;
    if (std::string problem = validateEmitters(def); !problem.empty()) return problem;
    return validateOutlets(def);
}

std::size_t countParticles(const WorldDef& def, int processes) {
    const float spacing = def.simulation.particleSpacing();
    double total = 0.0;
    for (const FluidBlock& b : def.fluidBlocks) {
        total += double(latticeCount(b.box, 0, spacing)) * double(latticeCount(b.box, 1, spacing)) *
                 double(latticeCount(b.box, 2, spacing));
    }
    if (total / std::max(1, processes) > 4e9)
        throw SceneError((def.source.empty() ? def.name : def.source) + ": fluid_blocks: " +
                         std::to_string(total) + " particles exceed the 32-bit particle index" +
                         (processes > 1 ? " of " + std::to_string(processes) + " processes" : ""));
    return static_cast<std::size_t>(total);
}

Vec3 pivotOf(const SolidDescription& d) {
    if (d.motion.hasPivot) return d.motion.pivot;
    using Kind = SolidDescription::Kind;
    switch (d.kind) {
        case Kind::Box:
            return (d.box.min + d.box.max) * 0.5f;
        case Kind::Sphere:
            return d.center;
        case Kind::Plane:
            return d.point;
        case Kind::Cylinder:
            return d.base + d.axis * (0.5f * d.height / length(d.axis));
        case Kind::Mesh:
            return d.transform.translation;
    }
    return {};
}

std::unique_ptr<SolidSet> buildSolids(const WorldDef& def) {
    auto set = std::make_unique<SolidSet>();
    const SimulationParams& sim = def.simulation;
    for (std::size_t i = 0; i < def.solids.size(); ++i) {
        const SolidDescription& d = def.solids[i];
        using Kind = SolidDescription::Kind;
        switch (d.kind) {
            case Kind::Box:
                set->add(makeBoxSolid(d.box));
                break;
            case Kind::Sphere:
                set->add(makeSphereSolid(d.center, d.radius));
                break;
            case Kind::Plane:
                set->add(makePlaneSolid(d.point, d.normal, sim.domain));
                break;
            case Kind::Cylinder:
                set->add(makeCylinderSolid(d.base, d.axis, d.radius, d.height));
                break;
            case Kind::Mesh: {
                MeshSolidOptions options;
                options.voxelSize = 0.5f * sim.particleRadius;
                options.bandWidth = sim.kernelRadius() + 2.0f * sim.particleRadius;
                options.shellThickness = sim.particleRadius;
                // The scale is baked into the distance field; rotation and
                // translation place it (its pose), so the solid can move.
                Transform scaleOnly;
                scaleOnly.scale = d.transform.scale;
                try {
                    set->add(loadMeshSolid(d.file, scaleOnly, options),
                             SolidMotion{d.transform.pose(), {}, {}});
                } catch (const SolidError& e) {
                    throw SceneError((def.source.empty() ? def.name : def.source) + ": " +
                                     fieldOf(d.field, "solids", i) + ".file: " + e.what());
                }
                break;
            }
        }
        set->setAdhesion(set->size() - 1, d.adhesion);
    }
    return set;
}

ParticleStore createParticles(const WorldDef& def, const SolidSet* solids, std::size_t* skipped,
                              const LocalFrame& frame) {
    return createParticles(def, solids, skipped, frame, 0, countParticles(def));
}

ParticleStore createParticles(const WorldDef& def, const SolidSet* solids, std::size_t* skipped,
                              const LocalFrame& frame, std::uint64_t siteBegin,
                              std::uint64_t siteEnd) {
    const SimulationParams& sim = def.simulation;
    const float r = sim.particleRadius;
    const float spacing = sim.particleSpacing();
    ParticleStore store;
    store.reserve(std::size_t(siteEnd - std::min(siteBegin, siteEnd)));
    std::size_t rejected = 0;
    std::uint64_t blockBegin = 0;  // the block's first site in the lattice order
    for (const FluidBlock& b : def.fluidBlocks) {
        const auto nx = std::uint64_t(latticeCount(b.box, 0, spacing)),
                   ny = std::uint64_t(latticeCount(b.box, 1, spacing)),
                   nz = std::uint64_t(latticeCount(b.box, 2, spacing));
        const std::uint64_t blockEnd = blockBegin + nx * ny * nz;
        // Counted in world coordinates (where the corners were rounded),
        // placed in the frame.
        const Vec3 min = frame.toFrame(b.box.min);
        // Sites in the order (k, j, i) of the block, from its part of the range.
        for (std::uint64_t s = std::max(siteBegin, blockBegin); s < std::min(siteEnd, blockEnd);
             ++s) {
            const std::uint64_t local = s - blockBegin;
            const std::uint64_t i = local % nx, j = local / nx % ny, k = local / (nx * ny);
            const Vec3 x =
                min + Vec3{r + float(i) * spacing, r + float(j) * spacing, r + float(k) * spacing};
            Vec3 normal;
            // A particle spawned inside (or touching) a solid would be shot
            // out of it: leave the site empty instead.
            if (solids && solids->signedDistance(x, r, normal) < r) {
                ++rejected;
                continue;
            }
            store.add(x, b.velocity, sim.fluid.restDensity);
        }
        blockBegin = blockEnd;
    }
    if (skipped) *skipped = rejected;
    return store;
}

std::size_t estimatedBytesPerParticle(const SimulationParams& params) {
    // Particle store (9 floats of state, density, id, reorder scratch) plus
    // solver scratch (lambda, delta, vorticity, grid keys, CSR offsets) plus
    // the neighbour list: ~(4/3) pi (h / 2r)^3 neighbours, 4 bytes each, with
    // the list's 25 % growth headroom.
    const double ratio = params.solver.kernelRadiusFactor / 2.0;
    const double neighbors = 4.0 / 3.0 * 3.14159265358979 * ratio * ratio * ratio;
    return static_cast<std::size_t>(4 * 13 + 4 * 8 + 8 + neighbors * 4 * 1.25 + 0.5);
}

void checkMemory(const WorldDef& def, std::size_t availableBytes, int processes,
                 int processesHere) {
    const std::size_t particles = countParticles(def, processes);
    // This machine's processes hold their shares (and their halos, about
    // the margin of the 25 % list headroom).
    const double needed = double(particles) * double(estimatedBytesPerParticle(def.simulation)) *
                          double(processesHere) / double(std::max(1, processes));
    if (needed > double(availableBytes))
        throw SceneError((def.source.empty() ? def.name : def.source) +
                         ": fluid_blocks: " + std::to_string(particles) + " particles need about " +
                         std::to_string(static_cast<long long>(needed / (1 << 20))) +
                         " MiB, more than the " + std::to_string(availableBytes >> 20) +
                         " MiB of memory available; use larger particles or smaller blocks");
}

void checkDeviceMemory(const WorldDef& def, BackendKind device, const std::string& description,
                       std::size_t availableBytes) {
    const std::size_t particles = countParticles(def);
    const double needed = double(particles) * double(deviceBytesPerParticle(
                                                  def.simulation, !def.rigidBodies.empty()));
    if (needed > double(availableBytes))
        throw SceneError((def.source.empty() ? def.name : def.source) +
                         ": fluid_blocks: " + std::to_string(particles) + " particles need about " +
                         std::to_string(static_cast<long long>(needed / (1 << 20))) +
                         " MiB on device " + std::string(backendName(device)) + " (" + description +
                         "), more than the " + std::to_string(availableBytes >> 20) +
                         " MiB free there; use larger particles or smaller blocks");
}

std::size_t availableMemoryBytes() {
    std::ifstream meminfo("/proc/meminfo");
    std::string line;
    while (std::getline(meminfo, line)) {
        std::istringstream words(line);
        std::string key;
        std::size_t kib = 0;
        if (words >> key >> kib && key == "MemAvailable:") return kib * 1024;
    }
    const long pages = ::sysconf(_SC_AVPHYS_PAGES);
    const long pageSize = ::sysconf(_SC_PAGESIZE);
    return pages > 0 && pageSize > 0 ? std::size_t(pages) * std::size_t(pageSize) : 0;
}

std::size_t peakResidentBytes() {
    struct rusage usage {};
    if (::getrusage(RUSAGE_SELF, &usage) != 0) return 0;
    return std::size_t(usage.ru_maxrss) * 1024;  // KiB on Linux
}

double speedLimit(const WorldDef& def) {
    if (def.guard.maxSpeed > 0.0f) return def.guard.maxSpeed;
    const SimulationParams& sim = def.simulation;
    const double diagonal = length(sim.domain.extent());
    double reference = std::sqrt(2.0 * double(length(sim.gravity)) * diagonal);
    double blockSpeed = 0.0;
    for (const FluidBlock& b : def.fluidBlocks)
        blockSpeed = std::max(blockSpeed, double(length(b.velocity)));
    reference += blockSpeed;
    if (!(reference > 0.0)) reference = diagonal * def.fps;
    return double(def.guard.maxSpeedFactor) * reference;
}

}  // namespace pbf
