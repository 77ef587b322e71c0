// The GPU backend's kernels (private header): one PBF_HD functor per stage
// of Algorithm 1 (Macklin & Mueller 2013), called for one particle index by
// thrust::for_each over a counting range. They hold raw pointers into
// device memory and call the reference backend's equations and neighbour
// sums (backend/reference/equations.hpp, neighbor_sums.hpp) and the shared
// boundary terms (backend/boundary.hpp) on the device's solids
// (device_solids.hpp): the maths the CPU build of this code is tested with
// is the maths the GPU runs.
//
// Every kernel writes only entry i of its outputs and reads the previous
// stage's arrays (Jacobi), so results do not depend on the order or the
// number of threads; no atomics anywhere.
#pragma once

#include <cstddef>
#include <cstdint>

#include "backend/boundary.hpp"
#include "backend/gpu/device_solids.hpp"
#include "backend/reference/equations.hpp"
#include "backend/reference/neighbor_sums.hpp"
#include "backend/sparse_grid.hpp"
#include "backend/statistics_partial.hpp"
#include "core/blocks.hpp"
#include "core/iteration_control.hpp"
#include "core/particle_checks.hpp"
#include "pbf/core/config.hpp"
#include "pbf/core/inlet_buffer.hpp"
#include "pbf/core/outlet_region.hpp"
#include "pbf/core/solver_constants.hpp"
#include "pbf/core/vec3.hpp"

namespace pbf::gpu::PBF_DEVICE_NAMESPACE {

// "No solid" in the 32-bit reaction records.
inline constexpr std::uint32_t kNoSolid32 = 0xffffffffu;

// A 3-vector attribute stored as three float arrays (structure of arrays).
struct Float3View {
    float* x = nullptr;
    float* y = nullptr;
    float* z = nullptr;
    PBF_HD Vec3 operator()(std::uint32_t i) const { return {x[i], y[i], z[i]}; }
    PBF_HD void set(std::uint32_t i, const Vec3& v) const {
        x[i] = v.x;
        y[i] = v.y;
        z[i] = v.z;
    }
};

// A float attribute.
struct FloatView {
    float* values = nullptr;
    PBF_HD float operator()(std::uint32_t i) const { return values[i]; }
};

// The sparse grid of the step's neighbour search on the device
// (backend/sparse_grid.hpp), with what the kernels look up per particle:
// its cell, the cell's block, and each block's 27 neighbouring blocks
// (found once per block per step).
struct DeviceGrid {
    grid::SparseGridView view;
    const std::uint32_t* particleCell = nullptr;  // cell of each sorted particle
    const std::uint32_t* cellBlock = nullptr;     // block of each cell
    const std::int32_t* blockNeighbors = nullptr; // 27 per block (-1: none)
};

// The neighbours of particle i as the reference's lists would hold them:
// the particles j != i of the 27 cells around i's cell (sparse_grid.hpp,
// the CPU backend's walk, cells farther than h skipped) that were closer than
// h at the neighbour search (`search`: x* when the grid was built). The
// iterations then move x*, but the set of pairs stays that of the search,
// as with the CPU and reference backends' lists; the kernels evaluate the
// pairs at the current positions (zero beyond h). In increasing index order.
struct StencilNeighbors {
    DeviceGrid grid;
    Float3View search;
    float radiusSquared = 0.0f;
    std::uint32_t i = 0;

    template <class Visit>
    PBF_HD void operator()(Visit&& visit) const {
        const Vec3 xi = search(i);
        const std::uint32_t cell = grid.particleCell[i];
        grid::CellNeighborhood nb;
        grid::cellNeighborhood(grid.view, cell, grid.blockNeighbors + 27 * grid.cellBlock[cell],
                               nb);
        grid::forEachStencilRange(grid.view, nb, xi,
                                  [&](std::uint32_t first, std::uint32_t last) {
                                      for (std::uint32_t j = first; j < last; ++j) {
                                          if (j == i) continue;
                                          if (lengthSquared(xi - search(j)) < radiusSquared)
                                              visit(j);
                                      }
                                  });
    }
};

// The grid of the step's neighbour search: walked once per step, to build
// the lists below.
struct SearchGrid {
    DeviceGrid grid;
    Float3View search;
    float radiusSquared = 0.0f;
    PBF_HD StencilNeighbors of(std::uint32_t i) const { return {grid, search, radiusSquared, i}; }
};

// The neighbours of particle i from the step's lists: the pairs of
// StencilNeighbors in its order, index[start[i]] .. index[start[i + 1] - 1],
// so every sum adds the same terms in the same order as the walk (the bits
// differ only where the compiler fuses multiply-adds differently: 2e-5 m
// after 8 substeps of the dam break on cuda-on-cpu). Built once per step;
// each of the step's eight or more passes then reads about 28 indices per
// particle where the walk tests about 216 candidates (27 cells of about 8).
// On an H200 the 1M dam break's step went from 8.1 to 4.9 ms
// (docs/performance.md, "GPU"), for 4 bytes per pair and 8 per particle.
struct ListNeighbors {
    const std::uint64_t* start = nullptr;
    const std::uint32_t* index = nullptr;
    std::uint32_t i = 0;

    template <class Visit>
    PBF_HD void operator()(Visit&& visit) const {
        const std::uint64_t end = start[i + 1];
        for (std::uint64_t k = start[i]; k < end; ++k) visit(index[k]);
    }
};

// The step's neighbour lists (DeviceBackend::buildNeighborLists).
struct NeighborLists {
    const std::uint64_t* start = nullptr;  // n + 1 entries
    const std::uint32_t* index = nullptr;
    PBF_HD ListNeighbors of(std::uint32_t i) const { return {start, index, i}; }
};

// The lists' first pass: how many neighbours particle i has (into start[i];
// an exclusive scan then makes the counts the offsets).
struct CountNeighbors {
    SearchGrid grid;
    std::uint64_t* count = nullptr;
    PBF_HD void operator()(std::uint32_t i) const {
        std::uint64_t n = 0;
        grid.of(i)([&](std::uint32_t) { ++n; });
        count[i] = n;
    }
};

// The lists' second pass: particle i's neighbours from its offset on.
struct FillNeighborLists {
    SearchGrid grid;
    const std::uint64_t* start = nullptr;
    std::uint32_t* index = nullptr;
    PBF_HD void operator()(std::uint32_t i) const {
        std::uint64_t k = start[i];
        grid.of(i)([&](std::uint32_t j) { index[k++] = j; });
    }
};

// The solids of a kernel: none, or the device view.
struct SolidsArgument {
    DeviceSolids solids;
    bool present = false;
    PBF_HD const DeviceSolids* get() const { return present ? &solids : nullptr; }
};

// One slot of reaction records (backend/reactions.hpp): which solid moved
// particle i, where, and by how much. Written for every particle by a
// recording stage (kNoSolid32 where none did), then folded into per-block
// sums (FoldReactions). Null `solid`: the stage records nothing.
struct ReactionSlot {
    std::uint32_t* solid = nullptr;
    Float3View at;
    Float3View move;
    PBF_HD bool active() const { return solid != nullptr; }
    PBF_HD void record(std::uint32_t i, std::size_t touched, const Vec3& x, const Vec3& d) const {
        solid[i] = touched == boundary::kNoSolid ? kNoSolid32 : static_cast<std::uint32_t>(touched);
        at.set(i, x);
        move.set(i, d);
    }
};

// Alg. 1 l. 1-3: v += dt g; x* = x + dt v, into the collision box.
struct PredictKernel {
    Aabb box;
    Vec3 gravity;
    float dt = 0.0f;
    Float3View position, velocity, predicted;
    PBF_HD void operator()(std::uint32_t i) const {
        const Vec3 v = velocity(i) + dt * gravity;
        velocity.set(i, v);
        predicted.set(i, boundary::clampToBox(box, position(i) + dt * v));
    }
};

// The warm start (reference::warmStart): x* += w dt^2 a for particles that
// ended their last substep compressed, kept in the collision box.
struct WarmStartKernel {
    SolverConstants c;
    float warm = 0.0f;  // solver.warm_start
    float dt = 0.0f;
    Float3View predicted, solveAcceleration;
    const float* density = nullptr;  // the last substep's: the warm start's test
    PBF_HD void operator()(std::uint32_t i) const {
        predicted.set(
            i, boundary::clampToBox(c.collisionBox,
                                    reference::warmStart(c, predicted(i), solveAcceleration(i),
                                                         density[i], warm, dt)));
    }
};

// Alg. 1 l. 4: the swept collision of x -> x* with the solids; records a
// coupled solid's push.
struct CollideSolidsKernel {
    SolverConstants c;
    DeviceSolids solids;
    Float3View position, predicted;
    ReactionSlot reactions;
    PBF_HD void operator()(std::uint32_t i) const {
        const Vec3 before = predicted(i);
        std::size_t touched = boundary::kNoSolid;
        const Vec3 x = boundary::resolveSolidCollision(c, solids, position(i), before, &touched);
        if (reactions.active()) reactions.record(i, touched, x, x - before);
        predicted.set(i, x);
    }
};

// The cell key of x*_i (core/cell_key.hpp) and the identity permutation,
// for the stable sort by cell.
struct CellKeyKernel {
    cell_key::CellFrame frame;
    Float3View predicted;
    std::uint64_t* keys = nullptr;
    std::uint32_t* order = nullptr;
    PBF_HD void operator()(std::uint32_t i) const {
        keys[i] = frame.keyOf(predicted(i));
        order[i] = i;
    }
};

// The sparse grid's pieces from the sorted keys: whether a particle is the
// first of its cell (index 0 is tested before its left neighbour is read:
// Thrust 1.17's unique_copy read the key before the first), a cell key's
// block, its bit in the block's mask; each block's 27 neighbouring blocks.
struct StartsCell {
    const std::uint64_t* keys = nullptr;
    PBF_HD bool operator()(std::uint32_t i) const { return i == 0 || keys[i] != keys[i - 1]; }
};
struct BlockOfKey {
    PBF_HD std::uint64_t operator()(std::uint64_t key) const { return key >> grid::kBlockShift; }
};
struct BitOfKey {
    PBF_HD std::uint64_t operator()(std::uint64_t key) const {
        return std::uint64_t{1} << (key & 63u);
    }
};
struct BlockNeighborhoodKernel {
    grid::SparseGridView view;
    std::int32_t* out = nullptr;
    PBF_HD void operator()(std::uint32_t b) const { grid::blockNeighborhood(view, b, out + 27 * b); }
};

// Eq. 1-2 and 8-11: rho_i and lambda_i at the current x*.
struct DensityLambdaKernel {
    SolverConstants c;
    SolidsArgument solids;
    NeighborLists search;
    Float3View predicted;
    float* density = nullptr;
    float* lambda = nullptr;
    PBF_HD void operator()(std::uint32_t i) const {
        const reference::DensityAndLambda r =
            reference::densityAndLambdaOf(c, solids.get(), search.of(i), predicted, i);
        density[i] = r.density;
        lambda[i] = r.lambda;
    }
};

// The iteration control's measure of particle i: C_i in fixed point
// (core/iteration_control.hpp), summed exactly in any order.
struct CompressionOf {
    SolverConstants c;
    const float* density = nullptr;
    PBF_HD std::int64_t operator()(std::uint32_t i) const {
        return fixedPointCompression(reference::densityConstraint(c, density[i]));
    }
};

// Eq. 12-14 and Alg. 1 l. 16-18: x* + omega dp into the collision box and
// out of the solids (swept from x), written to `corrected` (Jacobi: every
// particle reads the same x* and lambdas). Records the coupled solids'
// boundary term (slot 0) and projection (slot 1).
struct CorrectionKernel {
    SolverConstants c;
    SolidsArgument solids;
    NeighborLists search;
    Float3View position, predicted, corrected;
    FloatView lambda;
    ReactionSlot boundaryTerm, projection;
    PBF_HD void operator()(std::uint32_t i) const {
        const Vec3 dp =
            reference::positionCorrectionOf(c, solids.get(), search.of(i), predicted, lambda, i);
        const Vec3 xi = predicted(i);
        Vec3 moved = boundary::clampToBox(c.collisionBox, xi + reference::overRelaxed(c, dp));
        if (solids.present) {
            const Vec3 unprojected = moved;
            std::size_t touched = boundary::kNoSolid;
            moved = boundary::resolveSolidCollision(c, solids.solids, position(i), moved, &touched);
            if (boundaryTerm.active()) {
                const reference::SolidCorrection s =
                    reference::solidCorrectionOf(c, solids.solids, lambda(i), xi);
                boundaryTerm.record(i, s.solid, xi, reference::overRelaxed(c, s.displacement));
                projection.record(i, touched, moved, moved - unprojected);
            }
        }
        corrected.set(i, moved);
    }
};

// After the iterations, for the warm start: the step's pressure
// acceleration (reference::solveAcceleration, v still the predicted velocity).
struct RecordSolveAccelerationKernel {
    float dt = 0.0f;
    Float3View position, predicted, velocity, solveAcceleration;
    PBF_HD void operator()(std::uint32_t i) const {
        solveAcceleration.set(
            i, reference::solveAcceleration(position(i), predicted(i), velocity(i), dt));
    }
};

// Alg. 1 l. 21: v = (x* - x) / dt.
struct UpdateVelocityKernel {
    float dt = 0.0f;
    Float3View position, predicted, velocity;
    PBF_HD void operator()(std::uint32_t i) const {
        velocity.set(i, reference::velocityFromPositions(position(i), predicted(i), dt));
    }
};

// Alg. 1 l. 22, first pass: XSPH viscosity (eq. 17) into `post`, and the
// vorticity omega_i (eq. 15) when confinement is on, from v and the last
// density pass's rho (Jacobi).
struct XsphVorticityKernel {
    SolverConstants c;
    float viscosity = 0.0f;
    NeighborLists search;
    Float3View predicted, velocity, post, vorticity;  // vorticity.x null: confinement off
    FloatView density;
    PBF_HD void operator()(std::uint32_t i) const {
        const ListNeighbors neighbors = search.of(i);
        post.set(
            i, reference::xsphVelocityOf(c, viscosity, neighbors, predicted, velocity, density, i));
        if (vorticity.x)
            vorticity.set(i, reference::vorticityOf(c, neighbors, predicted, velocity, density, i));
    }
};

// Second pass: vorticity confinement (eq. 16) adds dt a_i to particle i's
// velocity (XSPH's result); it reads only the neighbours' omega and rho.
struct ConfinementKernel {
    SolverConstants c;
    float epsilon = 0.0f;
    float dt = 0.0f;
    NeighborLists search;
    Float3View predicted, vorticity, velocity;
    FloatView density;
    PBF_HD void operator()(std::uint32_t i) const {
        const Vec3 eta =
            reference::vorticityGradientOf(c, search.of(i), predicted, vorticity, density, i);
        velocity.set(
            i, velocity(i) + dt * reference::vorticityConfinement(c, epsilon, eta, vorticity(i)));
    }
};

// The physical viscosity (fluid.kinematic_viscosity, Monaghan 2005): adds
// dt nu lap v_i (reference::viscosityAccelerationOf, the walls as free-slip
// mirrors) to particle i's velocity (XSPH's result, when XSPH ran); the sum
// reads the velocities before XSPH from `before` (Jacobi, as XSPH reads
// them) and the last density pass's rho.
struct PhysicalViscosityKernel {
    SolverConstants c;
    float nu = 0.0f;
    float dt = 0.0f;
    NeighborLists search;
    Float3View predicted, before, velocity;
    FloatView density;
    PBF_HD void operator()(std::uint32_t i) const {
        const Vec3 a =
            reference::viscosityAccelerationOf(c, nu, search.of(i), predicted, before, density, i);
        velocity.set(i, velocity(i) + a * dt);
    }
};

// Surface tension: the cohesion of the surface layer and the
// walls' and solids' adhesion at the end-of-step x* with the last density
// pass's rho (reference::surfaceTensionOf), v_i += dt a_i. Reads only the
// neighbours' x* and rho, so it adds to v in place. Records a coupled
// solid's pull on the particle as the move dt^2 a (the CPU's reaction).
// The surface layer's weights s (reference::surfaceLayerOf), every particle's
// before the cohesion reads its neighbours'.
struct SurfaceLayerKernel {
    SolverConstants c;
    SolidsArgument solids;
    NeighborLists search;
    Float3View predicted;
    FloatView density, layer;
    PBF_HD void operator()(std::uint32_t i) const {
        layer.values[i] =
            reference::surfaceLayerOf(c, solids.get(), search.of(i), predicted, density(i), i);
    }
};

struct SurfaceTensionKernel {
    SolverConstants c;
    float wallAdhesion = 0.0f;
    float dt = 0.0f;
    SolidsArgument solids;
    NeighborLists search;
    Float3View predicted, velocity;
    FloatView layer;
    ReactionSlot reactions;
    PBF_HD void operator()(std::uint32_t i) const {
        const reference::SurfaceTensionAcceleration a = reference::surfaceTensionOf(
            c, wallAdhesion, solids.get(), search.of(i), predicted, layer, i);
        velocity.set(i, velocity(i) + dt * a.total);
        if (reactions.active())
            reactions.record(i, a.solid, predicted(i), (dt * dt) * a.solidAcceleration);
    }
};

// The curvature force's passes (reference::colourGradientOf, bandNormalOf,
// curvatureOf, curvatureForceVelocityChangeOf), one kernel per field, each
// launched after the previous has written every particle's.
struct ColourGradientKernel {
    SolverConstants c;
    NeighborLists search;
    Float3View predicted, gradient;
    PBF_HD void operator()(std::uint32_t i) const {
        gradient.set(i, reference::colourGradientOf(c, search.of(i), predicted, i));
    }
};

struct BandNormalKernel {
    SolverConstants c;
    NeighborLists search;
    Float3View predicted, gradient, normal;
    PBF_HD void operator()(std::uint32_t i) const {
        normal.set(i, reference::bandNormalOf(c, search.of(i), predicted, gradient, i));
    }
};

struct CurvatureKernel {
    SolverConstants c;
    NeighborLists search;
    Float3View predicted, gradient, normal;
    FloatView curvature;
    PBF_HD void operator()(std::uint32_t i) const {
        curvature.values[i] =
            reference::curvatureOf(c, search.of(i), predicted, gradient, normal, i);
    }
};

// v += dt a after surface tension's kernel (as the CPU adds it after the
// cohesion).
struct CurvatureForceKernel {
    SolverConstants c;
    float dt = 0.0f;
    NeighborLists search;
    Float3View predicted, velocity, gradient;
    FloatView curvature;
    PBF_HD void operator()(std::uint32_t i) const {
        const Vec3 dv = reference::curvatureForceVelocityChangeOf(c, dt, search.of(i), predicted,
                                                                  gradient, curvature, i);
        velocity.set(i, velocity(i) + dv);
    }
};

// Restitution and friction on the walls and solids, then x = x* (Alg. 1
// l. 23). Records a coupled solid's velocity change dv as the move dv dt.
struct RespondCommitKernel {
    SolverConstants c;
    float restitution = 0.0f;
    float friction = 0.0f;
    float dt = 0.0f;
    SolidsArgument solids;
    Float3View predicted, velocity, position;
    ReactionSlot reactions;
    PBF_HD void operator()(std::uint32_t i) const {
        const Vec3 x = predicted(i);
        Vec3 v = boundary::respondToWalls(c, restitution, friction, x, velocity(i));
        if (solids.present) {
            const Vec3 before = v;
            std::size_t touched = boundary::kNoSolid;
            v = boundary::respondToSolids(solids.solids, c.particleRadius, restitution, friction, x,
                                          v, &touched);
            if (reactions.active()) reactions.record(i, touched, x, (v - before) * dt);
        }
        velocity.set(i, v);
        position.set(i, x);
    }
};

// The coupled solids' reaction records of one stage folded into per-block
// sums: block b (detail::kBlockSize particle indices) adds its particles'
// records in index order, slot by slot, into sums[b][solid] (six doubles:
// the moves and their moments about the solid's origin), exactly as
// ReactionAccumulator::add does on the host. One thread per block: fixed
// order, no atomics.
struct FoldReactions {
    std::uint32_t particles = 0;
    std::uint32_t solidCount = 0;
    const std::uint8_t* coupled = nullptr;
    const Vec3* origins = nullptr;
    ReactionSlot slots[2];
    int slotCount = 1;
    double* sums = nullptr;  // [block][solid][6]
    PBF_HD void operator()(std::uint32_t block) const {
        const std::uint32_t begin = block * static_cast<std::uint32_t>(detail::kBlockSize);
        const std::uint32_t end = begin + static_cast<std::uint32_t>(detail::kBlockSize) < particles
                                      ? begin + static_cast<std::uint32_t>(detail::kBlockSize)
                                      : particles;
        for (std::uint32_t i = begin; i < end; ++i)
            for (int s = 0; s < slotCount; ++s) {
                const std::uint32_t k = slots[s].solid[i];
                if (k >= solidCount || !coupled[k]) continue;
                const Vec3 d = slots[s].move(i);
                const Vec3 moment = cross(slots[s].at(i) - origins[k], d);
                double* sum = sums + (std::size_t(block) * solidCount + k) * 6;
                sum[0] += d.x;
                sum[1] += d.y;
                sum[2] += d.z;
                sum[3] += moment.x;
                sum[4] += moment.y;
                sum[5] += moment.z;
            }
    }
};

// Solid k's total over the blocks, in block order.
struct TotalReactions {
    std::uint32_t blocks = 0;
    std::uint32_t solidCount = 0;
    const double* sums = nullptr;
    double* totals = nullptr;  // [solid][6]
    PBF_HD void operator()(std::uint32_t k) const {
        double t[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
        for (std::uint32_t b = 0; b < blocks; ++b)
            for (int a = 0; a < 6; ++a) t[a] += sums[(std::size_t(b) * solidCount + k) * 6 + a];
        for (int a = 0; a < 6; ++a) totals[std::size_t(k) * 6 + a] = t[a];
    }
};

// |v_i|^2, for the largest speed (a max: exact in any order).
struct SpeedSquared {
    Float3View velocity;
    PBF_HD float operator()(std::uint32_t i) const { return lengthSquared(velocity(i)); }
};

// The state guard's test (core/particle_checks.hpp): i if particle i is
// bad, else the largest index; the minimum over all is the first bad one.
struct BadIndex {
    Float3View position, velocity;
    double limit2 = 0.0;
    PBF_HD std::uint64_t operator()(std::uint32_t i) const {
        return detail::badParticle(position(i), velocity(i), limit2) ? std::uint64_t(i)
                                                                     : ~std::uint64_t(0);
    }
};

// Whether particle i stays: outside every outlet (pbf/core/outlet_region.hpp).
struct OutsideOutlets {
    Float3View position;
    const OutletRegion* outlets = nullptr;
    std::uint32_t count = 0;
    PBF_HD bool operator()(std::uint32_t i) const {
        return !insideAnyOutlet(outlets, count, position(i));
    }
};

// Gives particle i its inlet buffer's velocity when one holds it
// (Backend::driveInside).
struct DriveInBuffers {
    Float3View position;
    Float3View velocity;
    const InletBuffer* buffers = nullptr;
    std::uint32_t count = 0;
    PBF_HD void operator()(std::uint32_t i) const {
        Vec3 v;
        if (bufferVelocity(buffers, count, position(i), v)) velocity.set(i, v);
    }
};

// The statistics' partial sums of block b, in index order
// (backend/statistics_partial.hpp, as backend/statistics.cpp sums them).
struct StatisticsBlock {
    SolverConstants c;
    Aabb domain;
    SolidsArgument solids;
    float particleRadius = 0.0f;
    std::uint32_t particles = 0;
    Float3View position, velocity;
    const float* density = nullptr;
    detail::StatisticsPartial* partials = nullptr;
    PBF_HD void operator()(std::uint32_t block) const {
        const std::uint32_t begin = block * static_cast<std::uint32_t>(detail::kBlockSize);
        const std::uint32_t end = begin + static_cast<std::uint32_t>(detail::kBlockSize) < particles
                                      ? begin + static_cast<std::uint32_t>(detail::kBlockSize)
                                      : particles;
        detail::StatisticsPartial s;
        for (std::uint32_t i = begin; i < end; ++i)
            s.add(c, domain, solids.get(), particleRadius, position(i), velocity(i), density[i]);
        partials[block] = s;
    }
};

}  // namespace pbf::gpu::PBF_DEVICE_NAMESPACE
