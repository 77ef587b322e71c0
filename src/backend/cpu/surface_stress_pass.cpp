// The continuum surface stress on the CPU (equations.hpp, "Continuum
// surface stress"): the reference's own sums (neighbor_sums.hpp:
// surfaceStressOf, surfaceStressVelocityChangeOf) over the SIMD solver's
// neighbour lists, one particle at a time. Scalar: a SIMD pass like
// surface_tension_pass.cpp would be faster (docs/performance.md gives the
// cost of this one).
#include <cstdint>

#include "backend/cpu/solver_stages.hpp"
#include "backend/reference/neighbor_sums.hpp"

namespace pbf::stages {
namespace {

// Particle i's neighbour list as neighbor_sums.hpp visits it.
struct ListNeighbors {
    NeighborList list;
    template <class Visit>
    void operator()(Visit&& visit) const {
        for (std::size_t k = 0; k < list.size(); ++k) visit(list[k]);
    }
};

// x* from the packed records.
struct PackedPositions {
    const PackedPoint* points;
    Vec3 operator()(std::uint32_t k) const { return {points[k].x, points[k].y, points[k].z}; }
};

struct Stresses {
    const Sym3* values;
    Sym3 operator()(std::uint32_t k) const { return values[k]; }
};

}  // namespace

void computeSurfaceStress(const SolverConstants& c, const SolidSet* solids,
                          const NeighborSearch& search, const PackedPoint* predicted, Sym3* stress,
                          std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
        stress[i] = reference::surfaceStressOf(c, solids, ListNeighbors{search.neighbors(i)},
                                               PackedPositions{predicted}, std::uint32_t(i));
}

void applySurfaceStress(const SolverConstants& c, float dt, const NeighborSearch& search,
                        const PackedPoint* predicted, const Sym3* stress, Float3Array& velocity,
                        std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
        const Vec3 dv = reference::surfaceStressVelocityChangeOf(
            c, dt, ListNeighbors{search.neighbors(i)}, PackedPositions{predicted}, Stresses{stress},
            std::uint32_t(i));
        velocity.set(i, velocity.get(i) + dv);
    }
}

}  // namespace pbf::stages
