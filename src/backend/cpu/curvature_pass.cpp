// The scalar passes of surface tension on the CPU: the surface layer's
// weights (equations.hpp, "Strands") and the curvature force's four passes
// ("Curvature force"): the reference's per-particle sums (neighbor_sums.hpp)
// over the solver's neighbour lists and packed x*, so that the CPU, the
// reference and the device backends compute the same terms in the same order.
#include <cstddef>
#include <cstdint>

#include "backend/cpu/solver_stages.hpp"
#include "backend/reference/neighbor_sums.hpp"

namespace pbf::stages {
namespace {

// A neighbour list as neighbor_sums.hpp visits it.
struct ListNeighbors {
    NeighborList list;
    template <class Visit>
    void operator()(Visit&& visit) const {
        for (std::size_t k = 0; k < list.size(); ++k) visit(list[k]);
    }
};

struct PackedPositions {
    const PackedPoint* records;
    Vec3 operator()(std::uint32_t j) const { return {records[j].x, records[j].y, records[j].z}; }
};

struct VectorField {
    const Float3Array* values;
    Vec3 operator()(std::uint32_t j) const { return values->get(j); }
};

struct ScalarField {
    const float* values;
    float operator()(std::uint32_t j) const { return values[j]; }
};

std::uint32_t index(std::size_t i) {
    return static_cast<std::uint32_t>(i);
}

}  // namespace

void computeSurfaceLayer(const SolverStep& s, std::size_t begin, std::size_t end) {
    const SolverConstants& c = s.context.constants;
    const NeighborSearch& search = s.search;
    const PackedPoint* predicted = s.predicted;
    const float* density = s.particles.density.data();
    float* layer = s.surfaceLayer;
    for (std::size_t i = begin; i < end; ++i)
        layer[i] = reference::surfaceLayerOf(c, s.solids, ListNeighbors{search.neighbors(i)},
                                             PackedPositions{predicted}, density[i], index(i));
}

void computeColourGradient(const SolverStep& s, std::size_t begin, std::size_t end) {
    const SolverConstants& c = s.context.constants;
    const NeighborSearch& search = s.search;
    const PackedPoint* predicted = s.predicted;
    Float3Array& gradient = *s.colourGradient;
    for (std::size_t i = begin; i < end; ++i)
        gradient.set(i, reference::colourGradientOf(c, ListNeighbors{search.neighbors(i)},
                                                    PackedPositions{predicted}, index(i)));
}

void computeBandNormal(const SolverStep& s, std::size_t begin, std::size_t end) {
    const SolverConstants& c = s.context.constants;
    const NeighborSearch& search = s.search;
    const PackedPoint* predicted = s.predicted;
    const Float3Array& gradient = *s.colourGradient;
    Float3Array& normal = *s.bandNormal;
    for (std::size_t i = begin; i < end; ++i)
        normal.set(i, reference::bandNormalOf(c, ListNeighbors{search.neighbors(i)},
                                              PackedPositions{predicted}, VectorField{&gradient},
                                              index(i)));
}

void computeCurvature(const SolverStep& s, std::size_t begin, std::size_t end) {
    const SolverConstants& c = s.context.constants;
    const NeighborSearch& search = s.search;
    const PackedPoint* predicted = s.predicted;
    const Float3Array& gradient = *s.colourGradient;
    const Float3Array& normal = *s.bandNormal;
    float* curvature = s.curvature;
    for (std::size_t i = begin; i < end; ++i)
        curvature[i] = reference::curvatureOf(c, ListNeighbors{search.neighbors(i)},
                                              PackedPositions{predicted}, VectorField{&gradient},
                                              VectorField{&normal}, index(i));
}

void applyCurvatureForce(const SolverStep& s, std::size_t begin, std::size_t end) {
    const SolverConstants& c = s.context.constants;
    const float dt = s.dt;
    const NeighborSearch& search = s.search;
    const PackedPoint* predicted = s.predicted;
    const Float3Array& gradient = *s.colourGradient;
    const float* curvature = s.curvature;
    Float3Array& velocity = s.particles.velocity;
    for (std::size_t i = begin; i < end; ++i)
        velocity.set(i, velocity.get(i) + reference::curvatureForceVelocityChangeOf(
                                              c, dt, ListNeighbors{search.neighbors(i)},
                                              PackedPositions{predicted}, VectorField{&gradient},
                                              ScalarField{curvature}, index(i)));
}

}  // namespace pbf::stages
