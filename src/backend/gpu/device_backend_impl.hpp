// The GPU backend's implementation (private header, included once by each
// build: build_on_gpu.cu with nvcc, build_on_cpu.cpp with Thrust's OpenMP
// device system; PBF_DEVICE_NAMESPACE names the build). Only Thrust
// algorithms the CUDA toolkit's CCCL and Debian's Thrust 1.17 share:
// device_vector, for_each_n, stable_sort_by_key, gather, lower_bound,
// transform_reduce, copy, copy_if, count_if, fill, reduce_by_key, transform
// (and, on a GPU, CUB's radix sort).
//
// One step (Macklin & Mueller 2013, Algorithm 1) is a StepPlan
// (backend/step_plan.hpp) with the CPU solver's stage names, each stage a
// for_each over the particles with a kernel of device_kernels.hpp
// (DeviceBackend::buildPlan):
//   predict, warm_start, collide_solids                       l. 1-4
//   sort_by_cell (keys, stable sort, sparse grid), reorder   l. 5-7
//   density_and_lambda, [compression_totals, convergence_check],
//   correct_positions (Jacobi)                                 l. 8-19
//   record_solve_acceleration, update_velocity, viscosity_and_vorticity,
//   [physical_viscosity], vorticity_confinement, [surface_tension,
//   curvature_force (its four kernels)],
//   boundary_response (x = x*)                                 l. 20-24
// The particle fields come from the one list (include/pbf/core/particle_fields.hpp):
// DeviceParticles has a member per field, and upload, download, append and
// the reorder visit them through it.
// Reductions (largest speed, first bad particle, statistics, the coupled
// solids' reactions, the tolerance's compression) are integer, max/min or
// per-block sums added in block order: deterministic on a GPU and under any
// OpenMP thread count, and the same blocks as the host's loops.
#pragma once

#include <thrust/binary_search.h>
#include <thrust/copy.h>
#include <thrust/count.h>
#include <thrust/device_free.h>
#include <thrust/device_malloc.h>
#include <thrust/device_vector.h>
#include <thrust/execution_policy.h>
#include <thrust/fill.h>
#include <thrust/for_each.h>
#include <thrust/functional.h>
#include <thrust/gather.h>
#include <thrust/iterator/counting_iterator.h>
#include <thrust/iterator/transform_iterator.h>
#include <thrust/reduce.h>
#include <thrust/scan.h>
#include <thrust/sort.h>
#include <thrust/transform.h>
#include <thrust/transform_reduce.h>
#if THRUST_DEVICE_SYSTEM == THRUST_DEVICE_SYSTEM_CUDA && !defined(THRUST_CUB_WRAPPED_NAMESPACE)
#include <cub/device/device_radix_sort.cuh>
#endif

#include <array>
#include <chrono>
#include <cmath>
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "backend/gpu/block_cache.hpp"
#include "backend/gpu/device_backend.hpp"
#include "backend/gpu/device_kernels.hpp"
#include "backend/gpu/device_solids.hpp"
#include "backend/gpu/device_step_arrays.hpp"
#include "backend/reactions.hpp"
#include "backend/step_plan.hpp"
#include "backend/step_terms.hpp"
#include "geometry/boundary_scale.hpp"
#include "pbf/core/particle_fields.hpp"
#include "pbf/core/particles.hpp"
#include "pbf/core/threading.hpp"

#if !defined(PBF_DEVICE_NAMESPACE) || !defined(PBF_DEVICE_KIND)
#error "define PBF_DEVICE_NAMESPACE (on_gpu, on_cpu) and PBF_DEVICE_KIND before including this"
#endif

// Thrust wrapped in a namespace of its own (a second Thrust in one program,
// tests/backend/gpu/build_on_cpu_thrust117.cpp): `thrust::` names it here.
#if defined(THRUST_CUB_WRAPPED_NAMESPACE)
namespace pbf::gpu::PBF_DEVICE_NAMESPACE {
namespace thrust = ::THRUST_CUB_WRAPPED_NAMESPACE::thrust;
}
#endif

namespace pbf::gpu::PBF_DEVICE_NAMESPACE {

template <class T>
using DeviceArray = thrust::device_vector<T>;

template <class T>
T* raw(DeviceArray<T>& a) {
    return thrust::raw_pointer_cast(a.data());
}
template <class T>
const T* raw(const DeviceArray<T>& a) {
    return thrust::raw_pointer_cast(a.data());
}

inline thrust::counting_iterator<std::uint32_t> indices(std::uint32_t first = 0) {
    return thrust::counting_iterator<std::uint32_t>(first);
}

// Runs kernel(i) for i in [0, n).
template <class Kernel>
void forEachIndex(std::size_t n, const Kernel& kernel) {
    if (n > 0) thrust::for_each_n(thrust::device, indices(), n, kernel);
}

// A small host array (outlets, inlet buffers) kept on the device, uploaded
// only when its values change.
template <class T>
struct UploadedOnChange {
    DeviceArray<T> device;
    std::vector<T> host;  // what `device` holds
    void upload(std::span<const T> values) {
        if (std::equal(values.begin(), values.end(), host.begin(), host.end())) return;
        host.assign(values.begin(), values.end());
        device.assign(values.begin(), values.end());
    }
};

template <class T>
std::size_t bytesOf(const DeviceArray<T>& a) {
    return a.capacity() * sizeof(T);
}

struct DeviceFloat3 {
    DeviceArray<float> x, y, z;
    std::size_t size() const { return x.size(); }
    void resize(std::size_t n) {
        x.resize(n);
        y.resize(n);
        z.resize(n);
    }
    void clear() { resize(0); }
    Float3View view() { return {raw(x), raw(y), raw(z)}; }
    std::size_t bytes() const { return bytesOf(x) + bytesOf(y) + bytesOf(z); }
};
inline std::size_t bytesOf(const DeviceFloat3& a) {
    return a.bytes();
}

// Thrust's temporary buffers (the sort's, the reductions'), passed as
// thrust::device(allocator): blocks of device memory kept between calls
// (backend/gpu/block_cache.hpp).
struct DeviceMalloc {
    char* operator()(std::size_t n) const {
        return thrust::raw_pointer_cast(thrust::device_malloc<char>(n));
    }
};
struct DeviceFree {
    void operator()(char* data) const { thrust::device_free(thrust::device_pointer_cast(data)); }
};
class ScratchAllocator : public BlockCache<DeviceMalloc, DeviceFree> {
  public:
    ScratchAllocator() : BlockCache(DeviceMalloc{}, DeviceFree{}) {}
};

// A field of the list (include/pbf/core/particle_fields.hpp) in device memory:
// three float arrays for a 3-vector, one array otherwise.
template <class T, int Components>
using DeviceFieldArray = std::conditional_t<Components == 3, DeviceFloat3, DeviceArray<T>>;

inline std::array<DeviceArray<float>*, 3> componentsOf(DeviceFloat3& a) {
    return {&a.x, &a.y, &a.z};
}
inline std::array<const DeviceArray<float>*, 3> componentsOf(const DeviceFloat3& a) {
    return {&a.x, &a.y, &a.z};
}
template <class T>
std::array<DeviceArray<T>*, 1> componentsOf(DeviceArray<T>& a) {
    return {&a};
}
template <class T>
std::array<const DeviceArray<T>*, 1> componentsOf(const DeviceArray<T>& a) {
    return {&a};
}

// The particle state in device memory: one member per field of the list,
// as ParticleStore has, and which optional fields are on.
struct DeviceParticles {
#define PBF_DEVICE_MEMBER(name, type, components, unit, kind, description) \
    DeviceFieldArray<type, components> name;
    PBF_PARTICLE_FIELDS(PBF_DEVICE_MEMBER)
#undef PBF_DEVICE_MEMBER
    std::uint64_t nextId = 0;
    std::uint32_t optionalOn = 0;  // ParticleStore::keptOptionalFields()
    std::size_t size() const {
        return id.size();
    }
    bool holdsValues(std::size_t field) const {
        return ParticleStore::fields()[field].kind != ParticleFieldKind::Optional ||
               ((optionalOn >> field) & 1u) != 0;
    }
};

// Calls fn(field, deviceArray) for every component array of every field
// of the list (the field's index in it).
template <class Particles, class Fn>
void forEachDeviceArray(Particles& d, Fn&& fn) {
    std::size_t field = 0;
#define PBF_VISIT_DEVICE_FIELD(name, type, components, unit, kind, description) \
    for (auto* array : componentsOf(d.name)) fn(field, *array);                 \
    ++field;
    PBF_PARTICLE_FIELDS(PBF_VISIT_DEVICE_FIELD)
#undef PBF_VISIT_DEVICE_FIELD
}

// Calls fn(field, deviceArray, hostVector) for every component array of
// every field, with the matching array of a ParticleStore.
template <class Particles, class Store, class Fn>
void forEachFieldArray(Particles& d, Store& store, Fn&& fn) {
    std::size_t field = 0;
#define PBF_VISIT_FIELD_PAIR(name, type, components, unit, kind, description)            \
    {                                                                                    \
        const auto device = componentsOf(d.name);                                        \
        const auto host = ::pbf::componentsOf(store.name);                               \
        for (std::size_t c = 0; c < device.size(); ++c) fn(field, *device[c], *host[c]); \
        ++field;                                                                         \
    }
    PBF_PARTICLE_FIELDS(PBF_VISIT_FIELD_PAIR)
#undef PBF_VISIT_FIELD_PAIR
}

// The solids in device memory (device_solids.hpp): the shapes (uploaded when
// the set's shapes change) and, before every step, their poses, velocities,
// bounds and couplings; the bodies' boundary-scale grids.
class DeviceSolidStore {
  public:
    // The device view of `solids` (null or empty: none). Shapes without
    // parameters are sampled `spacing` apart with `margin` around them.
    SolidsArgument update(const SolidSet* solids, float spacing, float margin) {
        SolidsArgument argument;
        if (!presentSolids(solids)) return argument;
        const std::size_t count = solids->size();
        uploadShapes(*solids, spacing, margin);
        uploadScales(*solids);
        std::vector<SolidMotion> motions(count);
        std::vector<std::uint8_t> identity(count), coupled(count);
        std::vector<Aabb> bounds(count);
        std::vector<Vec3> origins(count);
        std::vector<float> adhesions(count);
        for (std::size_t k = 0; k < count; ++k) {
            motions[k] = solids->motion(k);
            identity[k] = solids->identityPose(k) ? 1 : 0;
            coupled[k] = solids->coupled(k) ? 1 : 0;
            bounds[k] = solids->bounds(k);
            origins[k] = motions[k].pose.position;
            adhesions[k] = solids->adhesion(k);
        }
        motions_ = motions;
        identity_ = identity;
        coupled_ = coupled;
        bounds_ = bounds;
        origins_ = origins;
        adhesions_ = adhesions;
        DeviceSolids& v = argument.solids;
        v.count = static_cast<std::uint32_t>(count);
        v.shapes = raw(shapes_);
        v.motions = raw(motions_);
        v.identity = raw(identity_);
        v.bounds = raw(bounds_);
        v.coupled = raw(coupled_);
        v.scales = raw(scales_);
        v.adhesions = raw(adhesions_);
        v.moving = solids->anyMoving();
        argument.present = true;
        return argument;
    }
    const std::uint8_t* coupled() const { return raw(coupled_); }
    const Vec3* origins() const { return raw(origins_); }
    std::size_t bytes() const {
        return bytesOf(shapes_) + bytesOf(samples_) + bytesOf(motions_) + bytesOf(identity_) +
               bytesOf(coupled_) + bytesOf(bounds_) + bytesOf(origins_) + bytesOf(scales_) +
               bytesOf(scaleValues_) + bytesOf(adhesions_);
    }

  private:
    void uploadShapes(const SolidSet& solids, float spacing, float margin) {
        std::vector<const Solid*> keys(solids.size());
        for (std::size_t k = 0; k < solids.size(); ++k) keys[k] = &solids.shape(k);
        if (keys == shapeKeys_) return;
        std::vector<DeviceShape> shapes(keys.size());
        std::vector<std::size_t> offsets(keys.size(), 0);
        std::vector<float> values;
        for (std::size_t k = 0; k < keys.size(); ++k) {
            const ShapeData d = keys[k]->shapeData(spacing, margin);
            DeviceShape& s = shapes[k];
            static_cast<ShapeParameters&>(s) = d;
            if (d.kind == ShapeData::Kind::Samples) {
                s.samples = {d.origin, 1.0f / d.spacing, d.nx, d.ny, d.nz, nullptr};
                offsets[k] = values.size();
                values.insert(values.end(), d.values.begin(), d.values.end());
            }
        }
        samples_ = values;
        for (std::size_t k = 0; k < keys.size(); ++k)
            if (shapes[k].kind == ShapeData::Kind::Samples)
                shapes[k].samples.values = raw(samples_) + offsets[k];
        shapes_ = shapes;
        shapeKeys_ = keys;
    }

    void uploadScales(const SolidSet& solids) {
        std::vector<const BoundaryScale*> keys(solids.size());
        for (std::size_t k = 0; k < solids.size(); ++k) keys[k] = solids.boundaryScaleGrid(k);
        if (keys == scaleKeys_ && scales_.size() == keys.size()) return;
        std::vector<shape::GridSamples> grids(keys.size());
        std::vector<std::size_t> offsets(keys.size(), 0);
        std::vector<float> values;
        std::vector<const BoundaryScale*> copied;  // grids shared by bodies of one shape: once
        for (std::size_t k = 0; k < keys.size(); ++k) {
            if (!keys[k]) continue;
            grids[k] = keys[k]->samples();
            std::size_t first = 0;
            for (; first < k; ++first)
                if (keys[first] == keys[k]) break;
            if (first < k) {
                offsets[k] = offsets[first];
                continue;
            }
            offsets[k] = values.size();
            const shape::GridSamples& g = grids[k];
            values.insert(values.end(), g.values,
                          g.values + std::size_t(g.nx) * std::size_t(g.ny) * std::size_t(g.nz));
        }
        scaleValues_ = values;
        for (std::size_t k = 0; k < keys.size(); ++k)
            grids[k].values = keys[k] ? raw(scaleValues_) + offsets[k] : nullptr;
        scales_ = grids;
        scaleKeys_ = keys;
    }

    std::vector<const Solid*> shapeKeys_;
    std::vector<const BoundaryScale*> scaleKeys_;
    DeviceArray<DeviceShape> shapes_;
    DeviceArray<float> samples_;
    DeviceArray<SolidMotion> motions_;
    DeviceArray<std::uint8_t> identity_, coupled_;
    DeviceArray<Aabb> bounds_;
    DeviceArray<Vec3> origins_;
    DeviceArray<float> adhesions_;
    DeviceArray<shape::GridSamples> scales_;
    DeviceArray<float> scaleValues_;
};

#if defined(PBF_DEVICE_OPENMP)
// Thrust's OpenMP system runs its loops on the OpenMP default team: size it
// to pbf's thread count (pbf::setThreadCount) for the duration of a call.
class ThreadScope {
  public:
    ThreadScope() : saved_(omp_get_max_threads()) { omp_set_num_threads(threadCount()); }
    ~ThreadScope() { omp_set_num_threads(saved_); }
    ThreadScope(const ThreadScope&) = delete;
    ThreadScope& operator=(const ThreadScope&) = delete;

  private:
    int saved_;
};
#else
// A GPU's threads are the kernels' launch configurations (Thrust's choice).
struct ThreadScope {
    ThreadScope() {}  // user-provided: an unused scope is not a warning
};
#endif

using Clock = std::chrono::steady_clock;
inline double millisecondsSince(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// The per-step context of the device's stages (backend/step_plan.hpp).
struct DeviceStep : StepProgress {
    DeviceStep(const SolverContext& stepContext, float stepDt)
        : context(stepContext),
          terms(stepTerms(stepContext)),
          dt(stepDt),
          control(stepContext.params.solver) {
        maxIterations = control.maxIterations();
    }
    const SolverContext& context;
    StepTerms terms;  // the optional terms this step runs
    float dt;
    IterationControl control;
    SolidsArgument solids;         // the device's solids (present: any)
    NeighborLists search;          // the step's lists, valid from Stage::NeighborLists on
    std::int64_t compression = 0;  // sum of C_i, fixed point (tolerance mode)
};

class DeviceBackend final : public Backend {
  public:
    DeviceBackend(BackendKind kind, const SimulationParams& params)
        : kind_(kind),
          sampleSpacing_(0.5f * params.particleRadius),
          sampleMargin_(params.kernelRadius() + 2.0f * params.particleRadius) {
        if (!cell_key::domainFrame(params.domain, params.kernelRadius(), frame_))
            throw std::invalid_argument(
                "the domain is wider than the cell key's range (2^21 kernel radii)");
        keyBits_ = cell_key::keyBits(frame_.maxCoordinate + 1);
        buildPlan();
    }
    // The plan's stages refer to this backend.
    DeviceBackend(const DeviceBackend&) = delete;
    DeviceBackend& operator=(const DeviceBackend&) = delete;

    BackendKind kind() const override { return kind_; }
    std::size_t size() const override { return p_.size(); }
    const StageTimes& lastStageTimes() const override { return times_; }
    std::span<const SolidReaction> lastReactions() const override { return lastReactions_; }
    const ParticleStore* hostState() const override { return nullptr; }
    ParticleStore* mutableHostState() override { return nullptr; }

    void append(std::span<const Vec3> positions, std::span<const Vec3> velocities,
                float density) override {
        if (positions.size() != velocities.size())
            throw std::invalid_argument(
                "Backend::append: positions and velocities differ in length");
        if (positions.empty()) return;
        checkParticlesPerProcess(kind(), p_.size(), positions.size());
        ThreadScope threads;
        // The new particles as ParticleStore::add makes them (zeros in the
        // optional fields that are on), then copied behind the others.
        ParticleStore added;
        added.setNextId(p_.nextId);
        added.keepOptionalFields(p_.optionalOn);
        for (std::size_t k = 0; k < positions.size(); ++k)
            added.add(positions[k], velocities[k], density);
        const std::size_t old = p_.size();
        forEachFieldArray(p_, added, [&](std::size_t field, auto& array, const auto& values) {
            if (!p_.holdsValues(field)) return;
            array.resize(old + values.size());
            thrust::copy(values.begin(), values.end(), array.begin() + old);
        });
        p_.nextId = added.nextId();
        searchValid_ = false;
    }

    // The particles outside every outlet, kept in their order: their
    // indices by a stream compaction into the sort's order array (idle
    // between steps), then every field gathered as the reorder does.
    std::size_t removeInside(std::span<const OutletRegion> outlets) override {
        const std::size_t n = p_.size();
        if (outlets.empty() || n == 0) return 0;
        ThreadScope threads;
        outlets_.upload(outlets);  // a scene's outlets never change
        const OutsideOutlets outside{view(p_.position), raw(outlets_.device),
                                     static_cast<std::uint32_t>(outlets.size())};
        const auto kept = static_cast<std::size_t>(thrust::count_if(
            thrust::device(scratch_), indices(), indices(std::uint32_t(n)), outside));
        if (kept == n) return 0;
        order_.resize(kept);
        thrust::copy_if(thrust::device(scratch_), indices(), indices(std::uint32_t(n)),
                        order_.begin(), outside);
        reorder();
        searchValid_ = false;
        return n - kept;
    }

    void driveInside(std::span<const InletBuffer> buffers) override {
        const std::size_t n = p_.size();
        if (buffers.empty() || n == 0) return;
        ThreadScope threads;
        buffers_.upload(buffers);  // changes when a nozzle opens or closes
        forEachIndex(n, DriveInBuffers{view(p_.position), view(p_.velocity), raw(buffers_.device),
                                       static_cast<std::uint32_t>(buffers.size())});
    }

    void download(ParticleStore& out) const override {
        ThreadScope threads;
        out = ParticleStore();
        out.keepOptionalFields(p_.optionalOn);
        forEachFieldArray(p_, out, [&](std::size_t, const auto& array, auto& values) {
            values.resize(array.size());
            thrust::copy(array.begin(), array.end(), values.begin());
        });
        out.setNextId(p_.nextId);
    }

    void upload(ParticleStore state) override {
        checkParticlesPerProcess(kind(), 0, state.size());
        ThreadScope threads;
        const std::size_t n = state.size();
        p_.optionalOn = state.keptOptionalFields();
        forEachFieldArray(p_, state, [&](std::size_t field, auto& array, const auto& values) {
            if (values.size() != (p_.holdsValues(field) ? n : 0))
                throw std::invalid_argument(std::string("Backend::upload: field ") +
                                            ParticleStore::fields()[field].name + " holds " +
                                            std::to_string(values.size()) + " values for " +
                                            std::to_string(n) + " particles");
            array.resize(values.size());
            thrust::copy(values.begin(), values.end(), array.begin());
        });
        p_.nextId = state.nextId();
        searchValid_ = false;
    }

    // One step: the plan's stages (buildPlan), then the coupled solids'
    // reactions from their per-block sums.
    void step(const SolverContext& context, float dt) override {
        ThreadScope threads;
        DeviceStep s(context, dt);
        s.solids = solids_.update(context.solids, sampleSpacing_, sampleMargin_);
        prepare(s.terms, s.solids, context.solids);
        plan_.run(s, times_);
        finishReactions(context, dt);
        searchValid_ = true;
    }

    // The stages of a step, in order (tests, docs).
    const StepPlan<DeviceStep>& plan() const { return plan_; }

    float maxSpeed() const override {
        ThreadScope threads;
        const std::size_t n = p_.size();
        if (n == 0) return 0.0f;
        const float maxSquared = thrust::transform_reduce(
            thrust::device(scratch_), indices(), indices(std::uint32_t(n)),
            SpeedSquared{view(p_.velocity)}, 0.0f, thrust::maximum<float>());
        return std::sqrt(maxSquared);
    }

    std::optional<BadParticle> findBadParticle(double speedLimit) const override {
        ThreadScope threads;
        const std::size_t n = p_.size();
        if (n == 0) return std::nullopt;
        const BadIndex test{view(p_.position), view(p_.velocity),
                            detail::squaredSpeedLimit(speedLimit)};
        const std::uint64_t none = ~std::uint64_t(0);
        const std::uint64_t first =
            thrust::transform_reduce(thrust::device(scratch_), indices(), indices(std::uint32_t(n)),
                                     test, none, thrust::minimum<std::uint64_t>());
        if (first == none) return std::nullopt;
        const std::size_t i = first;
        const Vec3 x{p_.position.x[i], p_.position.y[i], p_.position.z[i]};
        const Vec3 v{p_.velocity.x[i], p_.velocity.y[i], p_.velocity.z[i]};
        return detail::describeBadParticle(i, p_.id[i], x, v, speedLimit);
    }

    StateStatistics statistics(const SolverContext& context) const override {
        ThreadScope threads;
        const std::size_t n = p_.size();
        const SolidsArgument solids = solids_.update(context.solids, sampleSpacing_, sampleMargin_);
        const std::size_t blocks = (n + detail::kBlockSize - 1) / detail::kBlockSize;
        partials_.resize(blocks);
        forEachIndex(blocks, StatisticsBlock{context.constants, context.params.domain, solids,
                                             context.params.particleRadius,
                                             static_cast<std::uint32_t>(n), view(p_.position),
                                             view(p_.velocity), raw(p_.density), raw(partials_)});
        std::vector<detail::StatisticsPartial> partials(blocks);
        thrust::copy(partials_.begin(), partials_.end(), partials.begin());
        detail::StatisticsPartial total;
        for (const detail::StatisticsPartial& s : partials) total += s;
        return detail::finishStatistics(total, n, context.constants);
    }

    BackendDiagnostics diagnostics() const override {
        BackendDiagnostics d;
        d.memoryBytes = memoryBytes();
        d.neighborsPerParticle = neighborsPerParticle();
        d.compactListShare = std::numeric_limits<double>::quiet_NaN();  // no lists: cell ranges
        return d;
    }

    // The kernels of one step run one at a time (device_backend.hpp: StageOutputs).
    StageOutputs runStages(const SolverContext& context, std::span<const Vec3> x,
                           std::span<const Vec3> xStar, float dt,
                           const SimulationParams* surfaceTension) {
        ThreadScope threads;
        ParticleStore state;
        for (std::size_t k = 0; k < x.size(); ++k) {
            state.add(x[k], {}, context.constants.restDensity);
            state.predicted.set(k, xStar[k]);
        }
        upload(std::move(state));
        const std::size_t n = p_.size();
        const SolidsArgument solids = solids_.update(context.solids, sampleSpacing_, sampleMargin_);
        const StepTerms terms = stepTerms(context);
        prepare(terms, solids, context.solids);
        sortByCell();
        reorder();
        buildNeighborLists();
        const SolverConstants& c = context.constants;
        const NeighborLists search = neighborLists();
        forEachIndex(n, DensityLambdaKernel{c, solids, search, p_.predicted.view(), raw(p_.density),
                                            raw(lambda_)});
        CorrectionKernel k;
        k.c = c;
        k.solids = solids;
        k.search = search;
        k.position = p_.position.view();
        k.predicted = p_.predicted.view();
        k.corrected = corrected_.view();
        k.lambda = {raw(lambda_)};
        forEachIndex(n, k);
        forEachIndex(n, UpdateVelocityKernel{dt, p_.position.view(), p_.predicted.view(),
                                             p_.velocity.view()});
        vorticity_.resize(n);
        post_.resize(n);
        forEachIndex(n, XsphVorticityKernel{c,
                                            context.params.fluid.viscosity,
                                            search,
                                            p_.predicted.view(),
                                            p_.velocity.view(),
                                            post_.view(),
                                            vorticity_.view(),
                                            {raw(p_.density)}});
        StageOutputs out;
        const auto vectors = [n](DeviceFloat3& a) {
            std::vector<float> xs(n), ys(n), zs(n);
            thrust::copy(a.x.begin(), a.x.end(), xs.begin());
            thrust::copy(a.y.begin(), a.y.end(), ys.begin());
            thrust::copy(a.z.begin(), a.z.end(), zs.begin());
            std::vector<Vec3> v(n);
            for (std::size_t i = 0; i < n; ++i) v[i] = {xs[i], ys[i], zs[i]};
            return v;
        };
        out.input.resize(n);
        thrust::copy(p_.id.begin(), p_.id.end(), out.input.begin());
        out.x = vectors(p_.position);
        out.xStar = vectors(p_.predicted);
        out.density.resize(n);
        thrust::copy(p_.density.begin(), p_.density.end(), out.density.begin());
        out.lambda.resize(n);
        thrust::copy(lambda_.begin(), lambda_.end(), out.lambda.begin());
        out.corrected = vectors(corrected_);
        out.velocity = vectors(p_.velocity);
        out.xsphVelocity = vectors(post_);
        out.vorticity = vectors(vorticity_);
        // The physical viscosity and surface tension from v = (x* - x) / dt
        // (p_.velocity, unchanged by XSPH above: its output is post_), each on a
        // copy of v in corrected_ (read back, no longer needed).
        const auto copyVelocity = [&](DeviceFloat3& to) {
            thrust::copy(p_.velocity.x.begin(), p_.velocity.x.end(), to.x.begin());
            thrust::copy(p_.velocity.y.begin(), p_.velocity.y.end(), to.y.begin());
            thrust::copy(p_.velocity.z.begin(), p_.velocity.z.end(), to.z.begin());
        };
        if (terms.physicalViscosity) {
            const float nu = context.params.fluid.kinematicViscosity;
            copyVelocity(corrected_);
            forEachIndex(n, PhysicalViscosityKernel{c,
                                                    nu,
                                                    1.0f,
                                                    search,
                                                    p_.predicted.view(),
                                                    p_.velocity.view(),
                                                    corrected_.view(),
                                                    {raw(p_.density)}});
            out.viscosityVelocity = vectors(corrected_);
        }
        if (surfaceTension) {
            const SolverConstants cs = SolverConstants::from(*surfaceTension);
            copyVelocity(corrected_);
            surfaceLayer_.resize(n);
            forEachIndex(n, SurfaceLayerKernel{cs,
                                               solids,
                                               search,
                                               p_.predicted.view(),
                                               {raw(p_.density)},
                                               {raw(surfaceLayer_)}});
            forEachIndex(n, SurfaceTensionKernel{cs,
                                                 surfaceTension->solver.wallAdhesion,
                                                 dt,
                                                 solids,
                                                 search,
                                                 p_.predicted.view(),
                                                 corrected_.view(),
                                                 {raw(surfaceLayer_)},
                                                 {}});
            out.surfaceTensionVelocity = vectors(corrected_);
            out.surfaceLayer.resize(n);
            thrust::copy(surfaceLayer_.begin(), surfaceLayer_.end(), out.surfaceLayer.begin());
            // The curvature force alone, on v = 0 with a step of 1 s: its
            // acceleration a.
            resizeCurvature(n);
            thrust::fill(corrected_.x.begin(), corrected_.x.end(), 0.0f);
            thrust::fill(corrected_.y.begin(), corrected_.y.end(), 0.0f);
            thrust::fill(corrected_.z.begin(), corrected_.z.end(), 0.0f);
            runCurvatureForce(cs, 1.0f, search, corrected_.view());
            out.curvatureAcceleration = vectors(corrected_);
        }
        return out;
    }

  private:
    void resizeCurvature(std::size_t n) {
        colourGradient_.resize(n);
        bandNormal_.resize(n);
        curvature_.resize(n);
    }
    // The curvature force's four kernels at x*, v += dt a into `velocity`.
    void runCurvatureForce(const SolverConstants& c, float dt, NeighborLists search,
                           Float3View velocity) {
        const std::size_t n = p_.size();
        forEachIndex(n, ColourGradientKernel{c, search, p_.predicted.view(),
                                             colourGradient_.view()});
        forEachIndex(n, BandNormalKernel{c, search, p_.predicted.view(), colourGradient_.view(),
                                         bandNormal_.view()});
        forEachIndex(n, CurvatureKernel{c, search, p_.predicted.view(), colourGradient_.view(),
                                        bandNormal_.view(), {raw(curvature_)}});
        forEachIndex(n, CurvatureForceKernel{c, dt, search, p_.predicted.view(), velocity,
                                             colourGradient_.view(), {raw(curvature_)}});
    }

    static Float3View view(const DeviceFloat3& a) {
        return const_cast<DeviceFloat3&>(a).view();  // kernels given it only read
    }
    // The sorted grid at x*, valid right after the sort and the reorder
    // (the lists are built from it, before the iterations move x*).
    SearchGrid searchGrid() const {
        const grid::SparseGridView g{frame_,
                                        raw(cellKey_),
                                        raw(cellStart_),
                                        cellCount_,
                                        raw(blockKey_),
                                        raw(blockFirstCell_),
                                        raw(blockMask_),
                                        blockCount_};
        return {{g, raw(particleCell_), raw(cellBlock_), raw(blockNeighbors_)},
                view(p_.predicted),
                frame_.cell * frame_.cell};
    }
    NeighborLists neighborLists() const { return {raw(listStart_), raw(listIndex_)}; }

    // The step's neighbour lists from the grid walk (kernels: CountNeighbors,
    // FillNeighborLists): the counts, their exclusive scan into offsets
    // (start[n] = the total), then the indices. Exact in any order.
    void buildNeighborLists() {
        const std::size_t n = p_.size();
        listStart_.resize(n + 1);
        const SearchGrid grid = searchGrid();
        forEachIndex(n, CountNeighbors{grid, raw(listStart_)});
        listStart_[n] = 0;
        thrust::exclusive_scan(thrust::device(scratch_), listStart_.begin(), listStart_.end(),
                               listStart_.begin());
        const std::uint64_t total = listStart_[n];
        // An eighth spare: no reallocation while the count drifts up.
        if (listIndex_.size() < total) listIndex_.resize(total + total / 8);
        forEachIndex(n, FillNeighborLists{grid, raw(listStart_), raw(listIndex_)});
    }

    // The average neighbour count of the last step's search (NaN before one).
    double neighborsPerParticle() const {
        ThreadScope threads;
        const std::size_t n = p_.size();
        if (!searchValid_ || n == 0) return std::numeric_limits<double>::quiet_NaN();
        const std::uint64_t total = listStart_[n];
        return double(total) / double(n);
    }

    // Sizes the step's scratch for n particles and these settings (no
    // allocation once the count and settings stop changing).
    void prepare(const StepTerms& terms, const SolidsArgument& solids, const SolidSet* hostSolids) {
        const std::size_t n = p_.size();
        // The last substep's acceleration follows the particles while the
        // warm start is on (zero for new ones), and is dropped when it is off.
        setOptionalField(ParticleField::solveAcceleration, terms.warmStart);
        keys_.resize(n);
        order_.resize(n);
        reactionsActive_ = solids.present && hostSolids->anyCoupled();
        // The step arrays these settings use (device_step_arrays.hpp).
#define PBF_SIZE_STEP_ARRAY(name, type, components, use) \
    if (stepArrayInUse(StepArrayUse::use, terms, reactionsActive_)) name##_.resize(n);
        PBF_DEVICE_STEP_ARRAYS(PBF_SIZE_STEP_ARRAY)
#undef PBF_SIZE_STEP_ARRAY
        if (reactionsActive_) {
            solidCount_ = solids.solids.count;
            const std::size_t blocks = (n + detail::kBlockSize - 1) / detail::kBlockSize;
            reactionSums_.resize(blocks * solidCount_ * 6);
            thrust::fill(reactionSums_.begin(), reactionSums_.end(), 0.0);
        }
    }

    // Switches an optional field on (zeros) or off (emptied), as
    // ParticleStore::keepOptionalField.
    void setOptionalField(ParticleField field, bool on) {
        const std::uint32_t bit = std::uint32_t{1} << static_cast<std::uint32_t>(field);
        if (on == ((p_.optionalOn & bit) != 0)) return;
        p_.optionalOn = on ? p_.optionalOn | bit : p_.optionalOn & ~bit;
        const std::size_t n = p_.size();
        forEachDeviceArray(p_, [&](std::size_t k, auto& array) {
            if (k != static_cast<std::size_t>(field)) return;
            array.clear();
            if (on) array.resize(n);  // value-initialised: zeros
        });
    }

    ReactionSlot slot(int k) {
        if (!reactionsActive_) return {};
        if (k == 0) return {raw(reactionSolid0_), reactionAt0_.view(), reactionMove0_.view()};
        return {raw(reactionSolid1_), reactionAt1_.view(), reactionMove1_.view()};
    }

    // Adds the records of the last recording stage (slots [0, slots)) to the
    // per-block sums.
    void foldReactions(int slots) {
        if (!reactionsActive_) return;
        const std::size_t n = p_.size();
        FoldReactions fold;
        fold.particles = static_cast<std::uint32_t>(n);
        fold.solidCount = solidCount_;
        fold.coupled = solids_.coupled();
        fold.origins = solids_.origins();
        fold.slots[0] = slot(0);
        fold.slots[1] = slot(1);
        fold.slotCount = slots;
        fold.sums = raw(reactionSums_);
        forEachIndex((n + detail::kBlockSize - 1) / detail::kBlockSize, fold);
    }

    void finishReactions(const SolverContext& context, float dt) {
        lastReactions_.clear();
        if (!reactionsActive_) return;
        const std::size_t blocks = (p_.size() + detail::kBlockSize - 1) / detail::kBlockSize;
        reactionTotals_.resize(std::size_t{solidCount_} * 6);
        forEachIndex(solidCount_, TotalReactions{static_cast<std::uint32_t>(blocks), solidCount_,
                                                 raw(reactionSums_), raw(reactionTotals_)});
        std::vector<double> totals(reactionTotals_.size());
        thrust::copy(reactionTotals_.begin(), reactionTotals_.end(), totals.begin());
        lastReactions_.resize(solidCount_);
        for (std::size_t k = 0; k < solidCount_; ++k)
            lastReactions_[k] =
                reactionFromSums(&totals[6 * k], context.constants.particleMass, dt);
    }

    // The stages of a step (backend/step_plan.hpp: the CPU solver's names
    // and StageTimes accounting) in Alg. 1's order: {stage, the member
    // function that runs its kernels over all particles, the term that
    // switches it on (none: always)}. No neighbour lists of the CPU's
    // blocks: the kernels walk the sorted grid's lists.
    void buildPlan() {
        using Part = StepPlan<DeviceStep>::Part;
        using T = StepTerms;
        using B = DeviceBackend;
        const auto run = [this](void (DeviceBackend::*stage)(DeviceStep&)) {
            return [this, stage](DeviceStep& s) { (this->*stage)(s); };
        };
        // Alg. 1 l. 1-7: prediction, collisions, the sorted grid.
        plan_.add(Part::Before, {Stage::Predict, run(&B::predict)});
        plan_.add(Part::Before, {Stage::WarmStart, run(&B::warmStart), whenOn(&T::warmStart)});
        plan_.add(Part::Before, {Stage::CollideSolids, run(&B::collideSolids), whenOn(&T::solids)});
        plan_.add(Part::Before, {Stage::SortByCell, [this](DeviceStep&) { sortByCell(); }});
        plan_.add(Part::Before, {Stage::Reorder, [this](DeviceStep&) { reorder(); }});
        plan_.add(Part::Before, {Stage::NeighborLists, run(&B::neighborListsStage)});
        // Alg. 1 l. 8-19: one density iteration (Jacobi), as the reference.
        plan_.add(Part::Iteration, {Stage::DensityAndLambda, run(&B::densityAndLambda)});
        plan_.add(Part::Iteration, {Stage::CompressionTotals, run(&B::compressionTotals),
                                    whenOn(&T::errorControlled)});
        plan_.add(Part::Iteration, {Stage::ConvergenceCheck, run(&B::convergenceCheck),
                                    whenOn(&T::errorControlled)});
        plan_.add(Part::Iteration, {Stage::CorrectPositions, run(&B::correctPositions)});
        // Alg. 1 l. 20-24: velocities, post-process, commit.
        plan_.add(Part::After, {Stage::RecordSolveAcceleration, run(&B::recordSolveAcceleration),
                                whenOn(&T::warmStart)});
        plan_.add(Part::After, {Stage::UpdateVelocity, run(&B::updateVelocity)});
        plan_.add(Part::After, {Stage::ViscosityAndVorticity, run(&B::viscosityAndVorticity),
                                whenOn(&T::viscosityPass)});
        plan_.add(Part::After, {Stage::PhysicalViscosity, run(&B::physicalViscosity),
                                whenOn(&T::physicalViscosity)});
        plan_.add(Part::After, {Stage::VorticityConfinement, run(&B::vorticityConfinement),
                                whenOn(&T::vorticity)});
        plan_.add(Part::After,
                  {Stage::SurfaceTension, run(&B::surfaceTension), whenOn(&T::cohesion)});
        plan_.add(Part::After,
                  {Stage::CurvatureForce, run(&B::curvatureForce), whenOn(&T::curvature)});
        plan_.add(Part::After, {Stage::BoundaryResponse, run(&B::respondAndCommit)});
    }

    // The plan's stages (buildPlan), one or two kernels each.
    void predict(DeviceStep& s) {
        forEachIndex(p_.size(),
                     PredictKernel{s.context.constants.collisionBox, s.context.params.gravity, s.dt,
                                   p_.position.view(), p_.velocity.view(), p_.predicted.view()});
    }
    void warmStart(DeviceStep& s) {
        forEachIndex(
            p_.size(),
            WarmStartKernel{s.context.constants, s.context.params.solver.warmStart, s.dt,
                            p_.predicted.view(), p_.solveAcceleration.view(), raw(p_.density)});
    }
    // Its reaction records are folded before the reorder: the blocks of
    // the particles' old order, as on the CPU.
    void collideSolids(DeviceStep& s) {
        forEachIndex(p_.size(),
                     CollideSolidsKernel{s.context.constants, s.solids.solids, p_.position.view(),
                                         p_.predicted.view(), slot(0)});
        foldReactions(1);
    }
    void neighborListsStage(DeviceStep& s) {
        buildNeighborLists();
        s.search = neighborLists();
    }
    void densityAndLambda(DeviceStep& s) {
        forEachIndex(p_.size(),
                     DensityLambdaKernel{s.context.constants, s.solids, s.search,
                                         p_.predicted.view(), raw(p_.density), raw(lambda_)});
    }
    // The tolerance's test (core/iteration_control.hpp): the compression
    // summed in fixed point, exact in any order.
    void compressionTotals(DeviceStep& s) {
        const std::size_t n = p_.size();
        s.compression =
            thrust::transform_reduce(thrust::device(scratch_), indices(), indices(std::uint32_t(n)),
                                     CompressionOf{s.context.constants, raw(p_.density)},
                                     std::int64_t{0}, thrust::plus<std::int64_t>());
    }
    void convergenceCheck(DeviceStep& s) {
        s.stopIterations =
            s.control.converged(s.corrections, averageCompression(s.compression, p_.size()));
    }
    void correctPositions(DeviceStep& s) {
        CorrectionKernel k;
        k.c = s.context.constants;
        k.solids = s.solids;
        k.search = s.search;
        k.position = p_.position.view();
        k.predicted = p_.predicted.view();
        k.corrected = corrected_.view();
        k.lambda = {raw(lambda_)};
        k.boundaryTerm = slot(0);
        k.projection = slot(1);
        forEachIndex(p_.size(), k);
        foldReactions(2);
        p_.predicted.x.swap(corrected_.x);
        p_.predicted.y.swap(corrected_.y);
        p_.predicted.z.swap(corrected_.z);
    }
    void recordSolveAcceleration(DeviceStep& s) {
        forEachIndex(p_.size(), RecordSolveAccelerationKernel{
                                    s.dt, p_.position.view(), p_.predicted.view(),
                                    p_.velocity.view(), p_.solveAcceleration.view()});
    }
    void updateVelocity(DeviceStep& s) {
        forEachIndex(p_.size(), UpdateVelocityKernel{s.dt, p_.position.view(), p_.predicted.view(),
                                                     p_.velocity.view()});
    }
    // XSPH and the vorticity read the velocities above and the last
    // density pass's densities (Jacobi: XSPH's output goes to post_,
    // then becomes v); confinement then adds to each particle's own v.
    void viscosityAndVorticity(DeviceStep& s) {
        const Float3View omega = s.terms.vorticity ? vorticity_.view() : Float3View{};
        forEachIndex(p_.size(), XsphVorticityKernel{s.context.constants,
                                                    s.context.params.fluid.viscosity,
                                                    s.search,
                                                    p_.predicted.view(),
                                                    p_.velocity.view(),
                                                    post_.view(),
                                                    omega,
                                                    {raw(p_.density)}});
        p_.velocity.x.swap(post_.x);
        p_.velocity.y.swap(post_.y);
        p_.velocity.z.swap(post_.z);
    }
    // The physical viscosity (fluid.kinematic_viscosity) reads the
    // velocities XSPH read (post_ after XSPH's swap; a copy when XSPH is
    // off) and adds dt a to XSPH's result, as the CPU stage does.
    void physicalViscosity(DeviceStep& s) {
        if (!s.terms.viscosityPass()) {
            thrust::copy(thrust::device, p_.velocity.x.begin(), p_.velocity.x.end(),
                         post_.x.begin());
            thrust::copy(thrust::device, p_.velocity.y.begin(), p_.velocity.y.end(),
                         post_.y.begin());
            thrust::copy(thrust::device, p_.velocity.z.begin(), p_.velocity.z.end(),
                         post_.z.begin());
        }
        forEachIndex(p_.size(), PhysicalViscosityKernel{s.context.constants,
                                                        s.context.params.fluid.kinematicViscosity,
                                                        s.dt,
                                                        s.search,
                                                        p_.predicted.view(),
                                                        post_.view(),
                                                        p_.velocity.view(),
                                                        {raw(p_.density)}});
    }
    void vorticityConfinement(DeviceStep& s) {
        forEachIndex(p_.size(), ConfinementKernel{s.context.constants,
                                                  s.context.params.fluid.vorticity,
                                                  s.dt,
                                                  s.search,
                                                  p_.predicted.view(),
                                                  vorticity_.view(),
                                                  p_.velocity.view(),
                                                  {raw(p_.density)}});
    }
    // Surface tension: the surface layer's weights s of every particle,
    // then cohesion and adhesion at x*, v += dt a; a coupled solid's pull is
    // folded into its reaction (as the CPU's ReactionAccumulator records it,
    // between confinement and the response).
    void surfaceTension(DeviceStep& s) {
        forEachIndex(p_.size(), SurfaceLayerKernel{s.context.constants,
                                                   s.solids,
                                                   s.search,
                                                   p_.predicted.view(),
                                                   {raw(p_.density)},
                                                   {raw(surfaceLayer_)}});
        forEachIndex(p_.size(), SurfaceTensionKernel{s.context.constants,
                                                     s.context.params.solver.wallAdhesion,
                                                     s.dt,
                                                     s.solids,
                                                     s.search,
                                                     p_.predicted.view(),
                                                     p_.velocity.view(),
                                                     {raw(surfaceLayer_)},
                                                     slot(0)});
        foldReactions(1);
    }
    // The curvature force: g, nb and kappa of every particle in turn, then
    // v += dt a.
    void curvatureForce(DeviceStep& s) {
        runCurvatureForce(s.context.constants, s.dt, s.search, p_.velocity.view());
    }
    void respondAndCommit(DeviceStep& s) {
        const SolverParams& solver = s.context.params.solver;
        forEachIndex(p_.size(),
                     RespondCommitKernel{s.context.constants, solver.restitution, solver.friction,
                                         s.dt, s.solids, p_.predicted.view(), p_.velocity.view(),
                                         p_.position.view(), slot(0)});
        foldReactions(1);
    }

    // Cell keys of x*, the stable sort by cell key (ties keep their order,
    // so the result does not depend on the thread count), and the sparse
    // grid (backend/sparse_grid.hpp): the occupied cells with their starts,
    // each particle's cell, the 64-cell rows with their masks and their 27
    // neighbouring blocks. Nothing is sized by the domain.
    void sortByCell() {
        const auto n = static_cast<std::uint32_t>(p_.size());
        forEachIndex(n, CellKeyKernel{frame_, p_.predicted.view(), raw(keys_), raw(order_)});
        sortKeys(n);
        if (n == 0) {
            cellCount_ = blockCount_ = 0;
            return;
        }
        // Occupied cells: where each starts (the particles whose key differs
        // from their left neighbour's), their keys, whose each particle is.
        const StartsCell startsCell{raw(keys_)};
        cellCount_ = static_cast<std::uint32_t>(
            thrust::count_if(thrust::device(scratch_), indices(), indices(n), startsCell));
        const std::uint32_t cells = cellCount_;
        cellKey_.resize(cells);
        cellStart_.resize(cells + 1);
        thrust::copy_if(thrust::device(scratch_), indices(), indices(n), cellStart_.begin(),
                        startsCell);
        thrust::gather(thrust::device(scratch_), cellStart_.begin(), cellStart_.begin() + cells,
                       keys_.begin(), cellKey_.begin());
        cellStart_[cells] = n;
        particleCell_.resize(n);
        thrust::lower_bound(thrust::device(scratch_), cellKey_.begin(), cellKey_.end(),
                            keys_.begin(), keys_.end(), particleCell_.begin());
        // Blocks: each cell's block key, their distinct values with the
        // cells' bits or'ed, each block's first cell, each cell's block.
        blockOfCell_.resize(cells);
        thrust::transform(thrust::device(scratch_), cellKey_.begin(), cellKey_.end(),
                          blockOfCell_.begin(), BlockOfKey{});
        blockKey_.resize(cells);
        blockMask_.resize(cells);
        const auto ends = thrust::reduce_by_key(
            thrust::device(scratch_), blockOfCell_.begin(), blockOfCell_.end(),
            thrust::make_transform_iterator(cellKey_.begin(), BitOfKey{}), blockKey_.begin(),
            blockMask_.begin(), thrust::equal_to<std::uint64_t>(), thrust::bit_or<std::uint64_t>());
        blockCount_ = static_cast<std::uint32_t>(ends.first - blockKey_.begin());
        blockKey_.resize(blockCount_);
        blockMask_.resize(blockCount_);
        blockFirstCell_.resize(blockCount_);
        thrust::lower_bound(thrust::device(scratch_), blockOfCell_.begin(), blockOfCell_.end(),
                            blockKey_.begin(), blockKey_.end(), blockFirstCell_.begin());
        cellBlock_.resize(cells);
        thrust::lower_bound(thrust::device(scratch_), blockKey_.begin(), blockKey_.end(),
                            blockOfCell_.begin(), blockOfCell_.end(), cellBlock_.begin());
        blockNeighbors_.resize(std::size_t{27} * blockCount_);
        forEachIndex(blockCount_,
                     BlockNeighborhoodKernel{searchGrid().grid.view, raw(blockNeighbors_)});
    }

    // The stable sort of (key, order) by key. On a GPU CUB's radix sort of
    // only the key bits the domain's cells use; Thrust's OpenMP system has a
    // stable merge sort.
    void sortKeys(std::uint32_t n) {
#if THRUST_DEVICE_SYSTEM == THRUST_DEVICE_SYSTEM_CUDA && !defined(THRUST_CUB_WRAPPED_NAMESPACE)
        keysAlt_.resize(n);
        orderAlt_.resize(n);
        cub::DoubleBuffer<std::uint64_t> keys(raw(keys_), raw(keysAlt_));
        cub::DoubleBuffer<std::uint32_t> order(raw(order_), raw(orderAlt_));
        std::size_t bytes = 0;
        cub::DeviceRadixSort::SortPairs(nullptr, bytes, keys, order, int(n), 0, keyBits_);
        sortTemp_.resize(bytes);
        cub::DeviceRadixSort::SortPairs(raw(sortTemp_), bytes, keys, order, int(n), 0, keyBits_);
        if (keys.Current() != raw(keys_)) {
            keys_.swap(keysAlt_);
            order_.swap(orderAlt_);
        }
#else
        (void)n;
        thrust::stable_sort_by_key(thrust::device(scratch_), keys_.begin(), keys_.end(),
                                   order_.begin());
#endif
    }

    // Every particle field of the list gathered by the sort's order (a
    // permutation; after an outlet's compaction, the particles that stay).
    void reorder() {
        const std::size_t n = order_.size();
        forEachDeviceArray(p_, [&](std::size_t field, auto& array) {
            if (!p_.holdsValues(field)) return;  // an optional field that is off
            using T = typename std::decay_t<decltype(array)>::value_type;
            if constexpr (std::is_same_v<T, float>) {
                gatherFloat_.resize(n);
                thrust::gather(thrust::device, order_.begin(), order_.end(), array.begin(),
                               gatherFloat_.begin());
                array.swap(gatherFloat_);
            } else if constexpr (std::is_same_v<T, std::uint64_t>) {
                // The ids: gathered into the sort's second key buffer, idle
                // until the next sort (which takes the old ids' memory back).
                keysAlt_.resize(n);
                thrust::gather(thrust::device, order_.begin(), order_.end(), array.begin(),
                               keysAlt_.begin());
                array.swap(keysAlt_);
            } else {  // a field of another type added to the list
                DeviceArray<T> gathered(n);
                thrust::gather(thrust::device, order_.begin(), order_.end(), array.begin(),
                               gathered.begin());
                array.swap(gathered);
            }
        });
    }

    std::size_t memoryBytes() const {
        std::size_t bytes = 0;
        forEachDeviceArray(p_, [&](std::size_t, const auto& array) { bytes += bytesOf(array); });
#define PBF_STEP_ARRAY_CAPACITY(name, type, components, use) bytes += bytesOf(name##_);
        PBF_DEVICE_STEP_ARRAYS(PBF_STEP_ARRAY_CAPACITY)
#undef PBF_STEP_ARRAY_CAPACITY
        bytes += bytesOf(keys_) + bytesOf(order_) + bytesOf(keysAlt_) + bytesOf(orderAlt_) +
                 bytesOf(sortTemp_) + bytesOf(particleCell_);
        bytes += bytesOf(cellKey_) + bytesOf(cellStart_) + bytesOf(blockOfCell_) +
                 bytesOf(cellBlock_) + bytesOf(blockKey_) + bytesOf(blockMask_) +
                 bytesOf(blockFirstCell_) + bytesOf(blockNeighbors_);
        bytes += bytesOf(listStart_) + bytesOf(listIndex_);
        bytes += bytesOf(gatherFloat_) + bytesOf(partials_);
        bytes += bytesOf(reactionSums_) + bytesOf(reactionTotals_) + solids_.bytes();
        bytes += scratch_.bytes();  // the sort's and the reductions' buffers
        return bytes;
    }

  public:
    // The bytes held in the particle fields and the step arrays, by their
    // sizes (device_backend.hpp: tested against the memory table).
    std::size_t particleArrayBytes() const {
        std::size_t bytes = 0;
        const auto add = [&bytes](const auto& array) {
            using T = typename std::decay_t<decltype(array)>::value_type;
            bytes += array.size() * sizeof(T);
        };
        forEachDeviceArray(p_, [&](std::size_t, const auto& array) { add(array); });
        const auto addField = [&](const auto& field) {
            for (const auto* array : componentsOf(field)) add(*array);
        };
#define PBF_STEP_ARRAY_SIZE(name, type, components, use) addField(name##_);
        PBF_DEVICE_STEP_ARRAYS(PBF_STEP_ARRAY_SIZE)
#undef PBF_STEP_ARRAY_SIZE
        return bytes;
    }

  private:

    BackendKind kind_;
    cell_key::CellFrame frame_;  // cells of the kernel radius from the domain's corner
    int keyBits_ = 0;            // key bits those cells use
    float sampleSpacing_;
    float sampleMargin_;
    DeviceParticles p_;
    StepPlan<DeviceStep> plan_;
    mutable DeviceSolidStore solids_;   // refreshed by every call given solids
    mutable ScratchAllocator scratch_;  // Thrust's temporary buffers
    // The step's arrays, one element per particle (device_step_arrays.hpp).
#define PBF_STEP_ARRAY_MEMBER(name, type, components, use) DeviceFieldArray<type, components> name##_;
    PBF_DEVICE_STEP_ARRAYS(PBF_STEP_ARRAY_MEMBER)
#undef PBF_STEP_ARRAY_MEMBER
    // The step's other scratch: the sort (keys, order; the radix sort's
    // second buffers and scratch) and the sparse grid (sortByCell).
    DeviceArray<std::uint64_t> keys_, keysAlt_;
    DeviceArray<std::uint32_t> order_, orderAlt_;
    UploadedOnChange<OutletRegion> outlets_;  // removeInside's regions
    UploadedOnChange<InletBuffer> buffers_;   // driveInside's buffers
    DeviceArray<std::uint8_t> sortTemp_;
    DeviceArray<std::uint64_t> cellKey_, blockOfCell_, blockKey_, blockMask_;
    DeviceArray<std::uint32_t> cellStart_, particleCell_, cellBlock_, blockFirstCell_;
    DeviceArray<std::int32_t> blockNeighbors_;
    std::uint32_t cellCount_ = 0, blockCount_ = 0;
    DeviceArray<std::uint64_t> listStart_;  // the neighbour lists' offsets (n + 1)
    DeviceArray<std::uint32_t> listIndex_;  // their neighbours' indices
    DeviceArray<float> gatherFloat_;
    mutable DeviceArray<detail::StatisticsPartial> partials_;
    // Coupled solids' reactions: two record slots (step arrays), per-block
    // sums, totals.
    bool reactionsActive_ = false;
    std::uint32_t solidCount_ = 0;
    DeviceArray<double> reactionSums_;
    DeviceArray<double> reactionTotals_;
    std::vector<SolidReaction> lastReactions_;
    bool searchValid_ = false;  // the lists and cellStart_ are those of the current particles
    StageTimes times_;
};

}  // namespace pbf::gpu::PBF_DEVICE_NAMESPACE

namespace pbf::gpu::PBF_DEVICE_NAMESPACE {

StageOutputs runStages(const SimulationParams& params, const SolidSet* solids,
                       std::span<const Vec3> x, std::span<const Vec3> xStar, float dt,
                       const SimulationParams* surfaceTension) {
    const SolverConstants constants = SolverConstants::from(params);
    DeviceBackend backend(PBF_DEVICE_KIND, params);
    return backend.runStages({params, constants, solids}, x, xStar, dt, surfaceTension);
}

std::size_t particleArrayBytes(const Backend& backend) {
    return dynamic_cast<const DeviceBackend&>(backend).particleArrayBytes();
}

}  // namespace pbf::gpu::PBF_DEVICE_NAMESPACE
