// The Position Based Fluids solver (Macklin & Mueller 2013, Algorithm 1).
//
// One call of Solver::step advances the particles by dt:
//   predict        v += dt g;  x* = x + dt v                  (Alg. 1, l. 1-4)
//   neighbours     sort by grid cell, reorder, neighbour lists (l. 5-7)
//   iterations     rho_i, lambda_i; dp_i with s_corr; x* += dp; box projection (l. 8-19)
//   velocity       v = (x* - x) / dt                           (l. 21)
//   post-process   vorticity confinement, XSPH viscosity       (l. 22)
//   wall response  restitution and friction on the domain walls
//   commit         x = x*                                      (l. 23)
// Every stage is a function over particle ranges in solver_stages.hpp.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "pbf/kernels.hpp"
#include "pbf/neighbor_search.hpp"
#include "pbf/params.hpp"
#include "pbf/particles.hpp"
#include "pbf/solids.hpp"

namespace pbf {

// Density contribution of a flat wall of the domain box, tabulated against
// the distance s from the wall. The wall is modelled as the rest lattice
// continued beyond the plane (layers at s + r + k 2r), so a particle of the
// initial lattice next to a wall has exactly rest density and fluid at a wall
// is neither under-dense nor pulled towards it (the same role as the boundary
// particles of Akinci et al. 2012, here for the box in closed form).
struct WallTable {
    static constexpr int kSamples = 64;
    float range = 0.0f;                    // distances beyond this see no wall (h - r)
    float inverseStep = 0.0f;              // samples per metre
    float kernelSum[kSamples + 1] = {};    // sum over wall lattice of W, 1/m^3
    float gradientSum[kSamples + 1] = {};  // |sum of spiky grad W|, 1/m^4, points into the wall
};

// SI constants derived once from SimulationParams.
struct SolverConstants {
    float h = 0.0f;             // kernel radius, m
    float particleMass = 0.0f;  // kg, so that a full rest lattice has density rho0
    float restDensity = 0.0f;   // kg/m^3
    float inverseRestDensity = 0.0f;
    Poly6Kernel poly6;
    SpikyKernel spiky;
    // sum_k |grad_k C_i|^2 of an interior particle of the rest lattice, 1/m^2.
    // It converts the dimensionless relaxation and s_corr k to SI (units trap).
    float restGradientSum = 0.0f;
    float relaxationEpsilon = 0.0f;  // relaxation * restGradientSum
    // s_corr(r) = scorrScale * (W(r) / W(dq h))^n, scorrScale = -k / restGradientSum.
    float scorrScale = 0.0f;
    float scorrInverseWdq = 0.0f;  // 1 / W(dq h)
    int scorrExponent = 4;
    Aabb domain;        // walls of the box
    Aabb collisionBox;  // domain shrunk by the particle radius
    WallTable wall;

    static SolverConstants from(const SimulationParams& params);
};

// Four floats of one particle (x* and lambda, or v and rho), 16-byte aligned
// so that the SIMD neighbour loops load a neighbour's record whole.
struct alignas(16) PackedPoint {
    float x = 0.0f, y = 0.0f, z = 0.0f, w = 0.0f;
};

// Wall-clock milliseconds spent per stage in the last step.
struct StageTimes {
    double predict = 0.0;         // includes the swept collision with solids
    double neighborSearch = 0.0;  // sort, reorder, neighbour lists
    double solve = 0.0;           // all density iterations
    double postProcess = 0.0;     // velocity update, vorticity, XSPH, wall response
    double total = 0.0;
    // Parts of the above, for profiling (`pbf bench`).
    double gridBuild = 0.0;      // cell of each particle + counting sort
    double reorder = 0.0;        // permuting every particle array
    double neighborLists = 0.0;  // distance tests, CSR lists
    double lambda = 0.0;         // density + lambda passes, all iterations
    double deltaP = 0.0;  // correction passes with their box / solid projection, all iterations

    StageTimes& operator+=(const StageTimes& o);
    StageTimes operator*(double factor) const;
};

class Solver {
  public:
    // `solids` (may be null) are static obstacles the particles collide with.
    // `compactListSpan` (tests only): see NeighborSearch.
    explicit Solver(const SimulationParams& params,
                    std::shared_ptr<const SolidSet> solids = nullptr,
                    std::uint32_t compactListSpan = 65536);

    const SimulationParams& params() const { return params_; }
    const SolverConstants& constants() const { return constants_; }
    // Changes parameters that need no re-allocation (iterations, viscosity, ...).
    // Domain, radius and kernel factor must stay the same.
    void setParams(const SimulationParams& params);

    // Advances the particles by dt seconds.
    void step(ParticleStore& particles, float dt);

    const StageTimes& lastStageTimes() const { return times_; }
    const NeighborSearch& neighborSearch() const { return search_; }
    const SolidSet* solids() const { return solids_.get(); }
    // Solver-owned memory in bytes (scratch arrays, grid, neighbour lists).
    std::size_t memoryBytes() const;

  private:
    void ensureCapacity(std::size_t n);

    SimulationParams params_;
    SolverConstants constants_;
    std::shared_ptr<const SolidSet> solids_;
    NeighborSearch search_;
    StageTimes times_;

    // Scratch owned by the solver: sized once per particle count, reused every step.
    std::vector<std::uint32_t> perm_;
    // The iterations alternate between these (Jacobi): x* -> (x*, lambda) ->
    // corrected x*. The post-process reuses them for x* and (v, rho).
    std::vector<PackedPoint> packed_;
    std::vector<PackedPoint> packedWithLambda_;
    Float3Array vorticity_;  // omega_i, only while vorticity confinement is on
};

// Largest particle speed (m/s).
float maxSpeed(const ParticleStore& particles);

}  // namespace pbf
