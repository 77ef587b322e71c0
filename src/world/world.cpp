#include "pbf/world/world.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <limits>
#include <utility>

#include "bodies/rigid_bodies.hpp"
#include "pbf/core/distributed.hpp"
#include "pbf/core/param_table.hpp"

namespace pbf {

namespace {

// How deep the blocks reach along gravity: the distance between their
// highest and lowest corners (0 without gravity or blocks).
double depthAlong(const std::vector<FluidBlock>& blocks, const Vec3& gravity) {
    const double g = length(gravity);
    if (blocks.empty() || g <= 0.0) return 0.0;
    const Vec3 down = gravity * float(1.0 / g);
    double top = std::numeric_limits<double>::infinity(), bottom = -top;
    for (const FluidBlock& b : blocks)
        for (int corner = 0; corner < 8; ++corner) {
            const Vec3 x{(corner & 1) ? b.box.max.x : b.box.min.x,
                         (corner & 2) ? b.box.max.y : b.box.min.y,
                         (corner & 4) ? b.box.max.z : b.box.min.z};
            top = std::min(top, double(dot(x, down)));
            bottom = std::max(bottom, double(dot(x, down)));
        }
    return bottom - top;
}

}  // namespace

World::World(const WorldDef& def, const WorldOptions& options) : def_(def) {
    if (const std::string problem = validate(def_); !problem.empty())
        throw SceneError((def_.source.empty() ? def_.name : def_.source) + ": " + problem);
    // Refused before anything is allocated: a device that cannot run here, a
    // size that does not fit in its memory or in the host's.
    if (options.backend == BackendKind::Cuda || options.backend == BackendKind::CudaOnCpu) {
        const DeviceInfo device = deviceInfo(options.backend);
        if (!device.usable)
            throw std::runtime_error("device " + std::string(backendName(options.backend)) + ": " +
                                     device.description);
        // A device in host memory (cuda-on-cpu) has what the machine has.
        std::size_t limit = options.backendOptions.deviceMemoryBytes;
        if (limit == 0)
            limit = options.backend == BackendKind::CudaOnCpu ? availableMemoryBytes()
                                                              : device.freeBytes;
        if (limit > 0) checkDeviceMemory(def_, options.backend, device.description, limit);
    }
    const bool distributedRun = options.backend == BackendKind::Mpi;
    if (const std::size_t available = availableMemoryBytes(); available > 0)
        checkMemory(def_, available, distributedRun ? distributed::size() : 1,
                    distributedRun ? distributed::ranksHere() : 1);
    local_ = pbf::localFrame(def_.simulation.domain);
    localDef_ = inFrame(def_, local_);
    settings_ = def_.simulation;
    localSettings_ = localDef_.simulation;
    constants_ = SolverConstants::from(localSettings_);
    solids_ = buildSolids(localDef_);
    for (std::size_t i = 0; i < localDef_.solids.size(); ++i)
        if (localDef_.solids[i].motion.moves())
            driven_.push_back({i, solids_->motion(i).pose, pivotOf(localDef_.solids[i])});
    placeDrivenSolids(0.0);
    // Bodies add their surfaces to the solids, so no particle starts inside one.
    bodies_ = std::make_unique<detail::RigidBodies>(
        detail::BodiesSetup{def_.source.empty() ? def_.name : def_.source, localDef_.simulation,
                            localDef_.solids, localDef_.rigidBodies},
        *solids_);
    indexSolids();
    backend_ = makeBackend(options.backend, localSettings_, options.backendOptions);
    createParticles();
    for (const EmitterDescription& e : localDef_.emitters)
        emitters_.emplace_back(e, localSettings_);
    for (const OutletDescription& o : localDef_.outlets) outlets_.push_back(o.region);
    speedLimit_ = pbf::speedLimit(def_);
    startDepth_ = depthAlong(def_.fluidBlocks, settings_.gravity);
}

// One process creates every particle. A distributed backend's ranks each
// create an equal share of the lattice sites (the one-process order: sites
// in order, so the solid-distance work is even) and number their particles
// after those of the ranks before; the backend sends each to its owner.
void World::createParticles() {
    if (backend_->kind() != BackendKind::Mpi) {
        backend_->upload(pbf::createParticles(def_, solids_.get(), &skipped_, local_));
        return;
    }
    const std::uint64_t sites = countParticles(def_, distributed::size());
    const auto rank = std::uint64_t(distributed::rank()),
               ranks = std::uint64_t(distributed::size());
    std::size_t skipped = 0;
    ParticleStore part = pbf::createParticles(def_, solids_.get(), &skipped, local_,
                                              sites * rank / ranks, sites * (rank + 1) / ranks);
    const std::uint64_t first = distributed::sumOverRanksBefore(part.size());
    const std::uint64_t total = distributed::sumOverRanks(part.size());
    for (std::uint64_t& id : part.id) id += first;
    part.setNextId(total);
    skipped_ = std::size_t(distributed::sumOverRanks(skipped));
    backend_->uploadPart(std::move(part), first, total);
}

std::uint64_t World::emittedParticles() const {
    std::uint64_t emitted = 0;
    for (const Emitter& e : emitters_) emitted += e.emitted();
    return emitted;
}

World::~World() = default;
World::World(World&&) noexcept = default;
World& World::operator=(World&&) noexcept = default;

SolverContext World::context() const {
    return {localSettings_, constants_, solids_->empty() ? nullptr : solids_.get()};
}

void World::applySettings(const SimulationParams& settings) {
    const std::string prefix = def_.source.empty() ? "" : def_.source + ": ";
    if (const std::string problem = validate(settings); !problem.empty())
        throw SceneError(prefix + problem);
    // The parameters that shape the grid and the particles (the table's
    // rows that are not live) belong to the definition.
    for (const ParamInfo& param : paramTable())
        if (!param.live && !(param.get(settings) == param.get(def_.simulation)))
            throw SceneError(prefix + std::string(param.path) +
                             ": cannot change while the world runs");
    settings_ = settings;
    localSettings_ = settings;
    localSettings_.domain = localDef_.simulation.domain;
    constants_ = SolverConstants::from(localSettings_);
}

std::optional<StepError> World::checkState(int substep, double time, const char* stage) const {
    StepError error;
    error.kind = StepError::Kind::BadState;
    error.frame = frame_ + 1;
    error.substep = substep;
    error.stage = stage;
    if (const std::size_t body = bodies_->firstBadBody(); body < bodies_->size()) {
        const RigidBodyState& b = bodyStates()[body];
        error.message = fmt::format(
            "bad state in frame {} substep {} ({}, t = {:.6f} s): {} at ({:.6g}, {:.6g}, {:.6g}) "
            "with velocity ({:.6g}, {:.6g}, {:.6g}): not finite",
            error.frame, substep, stage, time, bodies_->infos()[body].field, b.position.x,
            b.position.y, b.position.z, b.velocity.x, b.velocity.y, b.velocity.z);
        return error;
    }
    std::optional<BadParticle> bad = backend_->findBadParticle(speedLimit_);
    if (!bad) return std::nullopt;
    bad->position = local_.toWorld(bad->position);
    error.message = fmt::format(
        "bad state in frame {} substep {} ({}, t = {:.6f} s): particle id {} at ({:.6g}, {:.6g}, "
        "{:.6g}): {}",
        error.frame, substep, stage, time, bad->id, bad->position.x, bad->position.y,
        bad->position.z, bad->problem);
    error.particle = *bad;
    return error;
}

double World::adaptiveSubstep(double remaining) const {
    const SolverParams& s = settings_.solver;
    const double maxDt = s.maxTimeStep;
    const double fastest =
        std::max({double(backend_->maxSpeed()), double(bodies_->maxSurfaceSpeed()), drivenSpeed_});
    const double speed = fastest + length(settings_.gravity) * maxDt;
    double dt = maxDt;
    if (speed > 0.0) dt = std::min(dt, s.cfl * settings_.particleSpacing() / speed);
    // The explicit viscosity's limit (FluidParams::kinematicViscosity): a
    // diffusion step nu dt / dx^2 of at most 0.05 (a 0.2 m Taylor-Green
    // vortex at r = 2.5 mm was stable at 0.05 and blew up at 0.1 before the
    // normalisation's factor was capped at 2).
    if (const double nu = settings_.fluid.kinematicViscosity; nu > 0.0) {
        const double spacing = settings_.particleSpacing();
        dt = std::min(dt, 0.05 * spacing * spacing / nu);
    }
    dt = std::min(dt, depthStep());
    dt = std::max(dt, frameDuration() / s.maxSubsteps);
    // Surface tension is explicit: capillary waves limit the step (infinite
    // when off). A limit of stability, so it overrides max_substeps too:
    // above it the cohesion flings particles off at tens of m/s.
    dt = std::min(dt, double(constants_.capillaryTimeStep));
    const double steps = std::max(1.0, std::ceil(remaining / dt - 1e-6));
    return remaining / steps;
}

// A fixed number of Jacobi iterations carries the support of a column only
// a few layers down per substep, so water starting at rest density falls
// until it reaches the bottom, and a column deep in the sense of
// Pi = (depth / spacing) (g dt^2 / spacing) / iterations slams and erupts:
// measured (4 iterations, a resting tank) settled at Pi = 0.06-0.12,
// splashed at 0.17 and erupted at 0.20-0.27 (docs/scenes.md, "Deep
// water"). Shrinking the step only once the compression shows (a feedback
// on the average compression) still erupted, at limits down to 0.5 %: the
// slam is under way before the average rises. So the bound is fixed for the
// world: the step at Pi = solver.depth_limit for the depth the fluid blocks
// start with.
double World::depthStep() const {
    const SolverParams& s = settings_.solver;
    const double g = length(settings_.gravity), spacing = settings_.particleSpacing();
    if (!(s.depthLimit > 0.0f) || s.maxDensityError > 0.0f || g <= 0.0 || !(startDepth_ > spacing))
        return std::numeric_limits<double>::infinity();
    return spacing * std::sqrt(double(s.depthLimit) * s.iterations / (g * startDepth_));
}

FrameResult World::stepFrame() {
    FrameResult result;
    try {
        applyHostEdits();
        downloadedValid_ = ownValid_ = false;
        ownDownloaded_ = ParticleStore();  // a rank's copy is not kept through the steps
        const SolverParams& s = settings_.solver;
        const double frameDt = frameDuration();
        FrameReport& report = result.report;
        double remaining = frameDt;
        int substeps = 0;
        // The guard runs on the state handed in (a script or a resumed
        // checkpoint may have put NaN there) and after every substep, so no
        // bad state reaches the frame's outputs.
        result.error = checkState(0, time_, "before the first solver step of the frame");
        if (result.error) return result;
        double elapsed = 0.0;
        std::vector<Vec3> emitted;
        std::vector<InletBuffer> buffers;
        // The bodies' contact world is rebuilt from their states once per
        // frame (bodies/contact_world.hpp); its time counts as `bodies`.
        const auto beginStart = std::chrono::steady_clock::now();
        bodies_->beginFrame(frameDt);
        const double beginMs =
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - beginStart)
                .count();
        report.stageMs.bodies += beginMs;
        report.stageMs.total += beginMs;
        while (remaining > 1e-12 * frameDt) {
            double dt = s.timeStepMode == TimeStepMode::Fixed ? frameDt / s.fixedSubsteps
                                                              : adaptiveSubstep(remaining);
            if (dt > remaining * (1.0 - 1e-9)) dt = remaining;  // the last step ends the frame
            const double stepStart = time_ + (frameDt - remaining);
            for (Emitter& emitter : emitters_) {
                emitted.clear();
                emitter.emit(stepStart, dt, solids_->empty() ? nullptr : solids_.get(), emitted);
                const std::vector<Vec3> velocities(emitted.size(), emitter.velocity());
                backend_->append(emitted, velocities, settings_.fluid.restDensity);
                report.emitted += emitted.size();
            }
            // Two-way coupling (bodies/rigid_bodies.hpp): the fluid steps
            // against the bodies' surfaces where they will be, then its
            // reaction moves the bodies.
            // Both halves of the bodies' work per substep (placing the
            // surfaces, and Bullet plus the new poses, each followed by the
            // solids' lookup grid) count as `bodies`.
            const auto placeStart = std::chrono::steady_clock::now();
            // Driven solids and bodies are where they will be at the
            // substep's end, as the fluid's positions will.
            placeDrivenSolids(stepStart + dt);
            bodies_->placeForFluid(dt, *solids_);
            indexSolids();
            const auto placeEnd = std::chrono::steady_clock::now();
            backend_->step(context(), static_cast<float>(dt));
            report.stageMs += backend_->lastStageTimes();
            // The water in front of an open nozzle leaves at the stream's
            // velocity (pbf/core/inlet_buffer.hpp).
            buffers.clear();
            for (const Emitter& emitter : emitters_)
                if (emitter.open(stepStart))
                    buffers.push_back(emitter.buffer(settings_.kernelRadius()));
            if (!buffers.empty()) backend_->driveInside(buffers);
            // Water that reached an outlet leaves before anything reads the
            // state (the guard, the bodies' next substep, the frame's files).
            if (!outlets_.empty()) {
                const std::size_t removed = backend_->removeInside(outlets_);
                report.removed += removed;
                removed_ += removed;
            }
            const auto bodiesStart = std::chrono::steady_clock::now();
            bodies_->advance(dt, settings_.gravity, backend_->lastReactions(), *solids_);
            indexSolids();
            const auto bodiesEnd = std::chrono::steady_clock::now();
            const double bodiesMs = std::chrono::duration<double, std::milli>(
                                        (placeEnd - placeStart) + (bodiesEnd - bodiesStart))
                                        .count();
            report.stageMs.bodies += bodiesMs;
            report.stageMs.total += bodiesMs;
            remaining -= dt;
            elapsed += dt;
            ++substeps;
            result.error = checkState(substeps, frame_ * frameDt + elapsed, "after solver step");
            if (result.error) return result;
        }
        ++frame_;
        time_ = frame_ * frameDt;  // no drift from summing substeps
        const FrameReport state = this->report();
        report.frame = state.frame;
        report.time = state.time;
        report.state = state.state;
        report.substeps = substeps;
        report.stepMs = substeps > 0 ? report.stageMs.total / substeps : 0.0;
        report.iterations = substeps > 0 ? report.stageMs.iterations / substeps : 0.0;
        refreshArrays();
    } catch (const std::exception& e) {
        StepError error;
        error.frame = frame_ + 1;
        error.message = fmt::format("frame {} failed: {}", frame_ + 1, e.what());
        result.error = std::move(error);
    }
    return result;
}

FrameReport World::report() const {
    FrameReport r;
    r.frame = frame_;
    r.time = time_;
    r.state = backend_->statistics(context());
    return r;
}

namespace {

void toWorld(ParticleStore& p, const LocalFrame& frame) {
    if (!frame.shifted()) return;
    for (std::size_t i = 0; i < p.size(); ++i) {
        p.position.set(i, frame.toWorld(p.position.get(i)));
        p.predicted.set(i, frame.toWorld(p.predicted.get(i)));
    }
}

}  // namespace

const ParticleStore& World::particles() const {
    const ParticleStore* host = backend_->hostState();
    if (host && !local_.shifted()) return *host;
    if (!downloadedValid_) {
        if (host)
            downloaded_ = *host;
        else
            backend_->download(downloaded_);
        toWorld(downloaded_, local_);
        downloadedValid_ = true;
    }
    return downloaded_;
}

const ParticleStore& World::ownParticles() const {
    if (backend_->kind() != BackendKind::Mpi) return particles();
    if (!ownValid_) {
        backend_->downloadPart(ownDownloaded_);
        toWorld(ownDownloaded_, local_);
        ownValid_ = true;
    }
    return ownDownloaded_;
}

void World::addParticles(std::span<const Vec3> positions, std::span<const Vec3> velocities) {
    if (positions.size() != velocities.size())
        throw std::invalid_argument("addParticles: " + std::to_string(positions.size()) +
                                    " positions but " + std::to_string(velocities.size()) +
                                    " velocities");
    applyHostEdits();
    std::vector<Vec3> local(positions.begin(), positions.end());
    for (Vec3& x : local) x = local_.toFrame(x);
    backend_->append(local, velocities, settings_.fluid.restDensity);
    downloadedValid_ = ownValid_ = false;
    refreshArrays();
}

ParticleArrays& World::arraysById() {
    if (!arrays_) {
        arrays_ = std::make_unique<ParticleArrays>();
        refreshArrays();
    }
    return *arrays_;
}

namespace {

// The row of each particle (memory order) in the id-ordered arrays: its id
// while the ids are 0 .. n - 1 (ids are unique, so all below n means
// exactly those), else its id's rank (after an outlet removed some).
std::vector<std::uint32_t> rowsById(const ParticleStore& p) {
    const std::size_t n = p.size();
    std::vector<std::uint32_t> rows(n);
    const auto largest = std::max_element(p.id.begin(), p.id.end());
    if (n == 0 || *largest < n) {
        for (std::size_t i = 0; i < n; ++i) rows[i] = std::uint32_t(p.id[i]);
        return rows;
    }
    const std::vector<std::uint32_t> order = p.orderById();
    for (std::size_t k = 0; k < n; ++k) rows[order[k]] = std::uint32_t(k);
    return rows;
}

}  // namespace

// Copies the backend's state into the id-ordered arrays (new buffers when
// the count changed, so that views of the old ones stay valid).
void World::refreshArrays() {
    if (!arrays_) return;
    const ParticleStore& p = particles();
    const std::size_t n = p.size();
    ParticleArrays& a = *arrays_;
    if (!a.position || a.count != n) {
        a.count = n;
        a.position = std::make_shared<std::vector<float>>(3 * n);
        a.velocity = std::make_shared<std::vector<float>>(3 * n);
        a.density = std::make_shared<std::vector<float>>(n);
        a.id = std::make_shared<std::vector<std::uint64_t>>(n);
    }
    float* x = a.position->data();
    float* v = a.velocity->data();
    const std::vector<std::uint32_t> rows = rowsById(p);
    for (std::size_t i = 0; i < n; ++i) {
        const std::size_t k = rows[i];
        x[3 * k + 0] = p.position.x[i];
        x[3 * k + 1] = p.position.y[i];
        x[3 * k + 2] = p.position.z[i];
        v[3 * k + 0] = p.velocity.x[i];
        v[3 * k + 1] = p.velocity.y[i];
        v[3 * k + 2] = p.velocity.z[i];
        (*a.density)[k] = p.density[i];
        (*a.id)[k] = p.id[i];
    }
    if (local_.shifted()) shownPositions_.assign(a.position->begin(), a.position->end());
}

// Writes the id-ordered positions and velocities (which a script may have
// changed) back into the backend. Copying unchanged values back changes no bit.
void World::applyHostEdits() {
    if (!arrays_ || arrays_->count != backend_->size()) return;
    ParticleStore* host = backend_->mutableHostState();
    ParticleStore copy;
    if (!host) {
        backend_->download(copy);
        host = &copy;
    }
    ParticleStore& p = *host;
    const float* x = arrays_->position->data();
    const float* v = arrays_->velocity->data();
    const bool shifted = local_.shifted();
    const std::vector<std::uint32_t> rows = rowsById(p);
    for (std::size_t i = 0; i < p.size(); ++i) {
        const std::size_t k = rows[i];
        const Vec3 shown{x[3 * k], x[3 * k + 1], x[3 * k + 2]};
        if (!shifted)
            p.position.set(i, shown);
        else if (!(shown == Vec3{shownPositions_[3 * k], shownPositions_[3 * k + 1],
                                 shownPositions_[3 * k + 2]}))
            p.position.set(i, local_.toFrame(shown));
        p.predicted.set(i, p.position.get(i));
        p.velocity.set(i, {v[3 * k], v[3 * k + 1], v[3 * k + 2]});
    }
    if (host == &copy) backend_->upload(std::move(copy));
    downloadedValid_ = ownValid_ = false;
}

void World::setSolidMotion(std::size_t i, const SolidMotion& motion) {
    if (i >= solids_->size())
        throw std::out_of_range("setSolidMotion: no solid " + std::to_string(i) +
                                " (the world has " + std::to_string(solids_->size()) + ")");
    if (solids_->coupled(i))
        throw std::invalid_argument("setSolidMotion: solid " + std::to_string(i) +
                                    " is a rigid body's surface; use setBodyState");
    for (const DrivenSolid& d : driven_)
        if (d.index == i)
            throw std::invalid_argument("setSolidMotion: solid " + std::to_string(i) +
                                        " has a prescribed motion (solids[" + std::to_string(i) +
                                        "].motion)");
    SolidMotion local = motion;
    local.pose.position = local_.toFrame(motion.pose.position);
    solids_->setMotion(i, local);
    indexSolids();
}

SolidMotion World::solidMotion(std::size_t i) const {
    SolidMotion motion = solids_->motion(i);
    motion.pose.position = local_.toWorld(motion.pose.position);
    return motion;
}

std::size_t World::bodyCount() const {
    return bodies_->size();
}
const std::vector<RigidBodyInfo>& World::bodyInfos() const {
    return bodies_->infos();
}
const std::vector<RigidBodyState>& World::bodyStates() const {
    if (!local_.shifted()) return bodies_->states();
    worldBodyStates_ = bodies_->states();
    for (RigidBodyState& b : worldBodyStates_) b.position = local_.toWorld(b.position);
    return worldBodyStates_;
}
const std::vector<RigidBodyLoad>& World::bodyLoads() const {
    return bodies_->loads();
}

void World::setBodyState(std::size_t i, const RigidBodyState& state) {
    if (i >= bodies_->size())
        throw std::out_of_range("setBodyState: no rigid body " + std::to_string(i) +
                                " (the world has " + std::to_string(bodies_->size()) + ")");
    RigidBodyState local = state;
    local.position = local_.toFrame(state.position);
    bodies_->setState(i, local, *solids_);
    indexSolids();
}

// The solids' lookup grid (SolidSet::buildIndex) with the largest reach the
// solver asks for: the sweep's move (under a CFL step) plus a kernel radius.
void World::indexSolids() {
    const float margin = constants_.h + 2.0f * settings_.particleRadius;
    const Vec3 pad{margin, margin, margin};
    const Aabb& domain = localDef_.simulation.domain;
    solids_->buildIndex({domain.min - pad, domain.max + pad}, margin);
}

// Places the solids with a prescribed motion where it puts them at `time`
// (pbf/geometry/prescribed_motion.hpp) and notes the fastest point of any
// of them (for the adaptive step): the speed of a rigid motion is largest
// at a corner of the shape's bounding box.
void World::placeDrivenSolids(double time) {
    drivenSpeed_ = 0.0;
    for (const DrivenSolid& d : driven_) {
        const SolidMotion motion =
            motionAt(localDef_.solids[d.index].motion, d.rest, d.pivot, time);
        solids_->setMotion(d.index, motion);
        const Aabb box = solids_->shape(d.index).bounds();
        for (int corner = 0; corner < 8; ++corner) {
            const Vec3 p{corner & 1 ? box.max.x : box.min.x, corner & 2 ? box.max.y : box.min.y,
                         corner & 4 ? box.max.z : box.min.z};
            drivenSpeed_ =
                std::max(drivenSpeed_, double(length(motion.velocityAt(motion.pose.toWorld(p)))));
        }
    }
}

WorldState World::captureState(bool ownPart) const {
    WorldState state;
    if (ownPart) {
        state.first = backend_->downloadPart(state.particles);
        state.total = backend_->size();
    } else {
        backend_->download(state.particles);
    }
    for (const Emitter& e : emitters_) state.emitters.push_back(e.state());
    state.bodies = bodies_->states();
    state.removed = removed_;
    state.frame = frame_;
    state.time = time_;
    return state;
}

void World::restoreState(WorldState state) {
    if (state.emitters.size() != emitters_.size())
        throw std::invalid_argument(
            "World::restoreState: " + std::to_string(state.emitters.size()) +
            " emitter states for " + std::to_string(emitters_.size()) + " emitters");
    if (state.bodies.size() != bodies_->size())
        throw std::invalid_argument("World::restoreState: " + std::to_string(state.bodies.size()) +
                                    " body states for " + std::to_string(bodies_->size()) +
                                    " rigid bodies");
    for (std::size_t k = 0; k < emitters_.size(); ++k) emitters_[k].setState(state.emitters[k]);
    placeDrivenSolids(state.time);
    bodies_->setStates(std::move(state.bodies), *solids_);
    indexSolids();
    if (state.total == 0)
        backend_->upload(std::move(state.particles));
    else
        backend_->uploadPart(std::move(state.particles), state.first, state.total);
    removed_ = state.removed;
    frame_ = state.frame;
    time_ = state.time;
    downloadedValid_ = ownValid_ = false;
    refreshArrays();
}

}  // namespace pbf
