#include "backend/reference/particle_sums.hpp"

namespace pbf::reference {
namespace {

// A neighbour list as neighbor_sums.hpp visits it.
struct ListNeighbors {
    NeighborIndices list;
    template <class Visit>
    void operator()(Visit&& visit) const {
        for (const std::uint32_t j : list) visit(j);
    }
};

// An array read by index.
template <class T>
struct Array {
    std::span<const T> values;
    T operator()(std::uint32_t k) const { return values[k]; }
};
template <class T>
Array(std::span<const T>) -> Array<T>;

std::uint32_t index(std::size_t i) {
    return static_cast<std::uint32_t>(i);
}

}  // namespace

DensityAndLambda densityAndLambda(const SolverConstants& c, const SolidSet* solids,
                                  std::span<const Vec3> x, NeighborIndices neighbors,
                                  std::size_t i) {
    return densityAndLambdaOf(c, solids, ListNeighbors{neighbors}, Array{x}, index(i));
}

Vec3 positionCorrection(const SolverConstants& c, const SolidSet* solids, std::span<const Vec3> x,
                        std::span<const float> lambdas, NeighborIndices neighbors, std::size_t i) {
    return positionCorrectionOf(c, solids, ListNeighbors{neighbors}, Array{x}, Array{lambdas},
                                index(i));
}

SolidCorrection solidCorrection(const SolverConstants& c, const SolidSet& solids, float lambdaI,
                                const Vec3& xi) {
    return solidCorrectionOf(c, solids, lambdaI, xi);
}

Vec3 xsphVelocity(const SolverConstants& c, float viscosity, std::span<const Vec3> x,
                  std::span<const Vec3> v, std::span<const float> rho, NeighborIndices neighbors,
                  std::size_t i) {
    return xsphVelocityOf(c, viscosity, ListNeighbors{neighbors}, Array{x}, Array{v}, Array{rho},
                          index(i));
}

Vec3 viscosityAcceleration(const SolverConstants& c, float nu, std::span<const Vec3> x,
                           std::span<const Vec3> v, std::span<const float> rho,
                           NeighborIndices neighbors, std::size_t i) {
    return viscosityAccelerationOf(c, nu, ListNeighbors{neighbors}, Array{x}, Array{v}, Array{rho},
                                   index(i));
}

Vec3 vorticity(const SolverConstants& c, std::span<const Vec3> x, std::span<const Vec3> v,
               std::span<const float> rho, NeighborIndices neighbors, std::size_t i) {
    return vorticityOf(c, ListNeighbors{neighbors}, Array{x}, Array{v}, Array{rho}, index(i));
}

Vec3 vorticityGradient(const SolverConstants& c, std::span<const Vec3> x,
                       std::span<const Vec3> omega, std::span<const float> rho,
                       NeighborIndices neighbors, std::size_t i) {
    return vorticityGradientOf(c, ListNeighbors{neighbors}, Array{x}, Array{omega}, Array{rho},
                               index(i));
}

SpreadAxes spreadAxes(const SolverConstants& c, std::span<const Vec3> x, NeighborIndices neighbors,
                      std::size_t i) {
    return spreadAxes(spreadOf(c, ListNeighbors{neighbors}, Array{x}, index(i)));
}

float surfaceLayer(const SolverConstants& c, const SolidSet* solids, std::span<const Vec3> x,
                   float density, NeighborIndices neighbors, std::size_t i) {
    return surfaceLayerOf(c, solids, ListNeighbors{neighbors}, Array{x}, density, index(i));
}

SurfaceTensionAcceleration surfaceTension(const SolverConstants& c, float wallAdhesion,
                                          const SolidSet* solids, std::span<const Vec3> x,
                                          std::span<const float> s, NeighborIndices neighbors,
                                          std::size_t i) {
    return surfaceTensionOf(c, wallAdhesion, solids, ListNeighbors{neighbors}, Array{x}, Array{s},
                            index(i));
}

Vec3 colourGradient(const SolverConstants& c, std::span<const Vec3> x, NeighborIndices neighbors,
                    std::size_t i) {
    return colourGradientOf(c, ListNeighbors{neighbors}, Array{x}, index(i));
}

Vec3 bandNormal(const SolverConstants& c, std::span<const Vec3> x, std::span<const Vec3> g,
                NeighborIndices neighbors, std::size_t i) {
    return bandNormalOf(c, ListNeighbors{neighbors}, Array{x}, Array{g}, index(i));
}

float curvature(const SolverConstants& c, std::span<const Vec3> x, std::span<const Vec3> g,
                std::span<const Vec3> nb, NeighborIndices neighbors, std::size_t i) {
    return curvatureOf(c, ListNeighbors{neighbors}, Array{x}, Array{g}, Array{nb}, index(i));
}

Vec3 curvatureForceVelocityChange(const SolverConstants& c, float dt, std::span<const Vec3> x,
                                  std::span<const Vec3> g, std::span<const float> kappa,
                                  NeighborIndices neighbors, std::size_t i) {
    return curvatureForceVelocityChangeOf(c, dt, ListNeighbors{neighbors}, Array{x}, Array{g},
                                          Array{kappa}, index(i));
}

}  // namespace pbf::reference
