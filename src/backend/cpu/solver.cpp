#include "pbf/solver.hpp"

#include <omp.h>

#include <chrono>
#include <cmath>
#include <stdexcept>

#include "core/parallel.hpp"
#include "backend/cpu/solver_stages.hpp"

namespace pbf {
namespace {

using Clock = std::chrono::steady_clock;

double millisecondsSince(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// Sums the kernels over the wall's lattice for distances s in [0, h - r].
WallTable makeWallTable(const SolverConstants& c, double radius, double spacing) {
    WallTable table;
    table.range = static_cast<float>(c.h - radius);
    table.inverseStep = WallTable::kSamples / table.range;
    const int reach = static_cast<int>(std::ceil(c.h / spacing));
    for (int sample = 0; sample <= WallTable::kSamples; ++sample) {
        const double s = double(sample) / table.inverseStep;
        double kernelSum = 0.0, gradientSum = 0.0;
        for (int layer = 0; s + radius + layer * spacing < c.h; ++layer) {
            const double depth = s + radius + layer * spacing;  // normal distance to the layer
            for (int a = -reach; a <= reach; ++a)
                for (int b = -reach; b <= reach; ++b) {
                    const Vec3 rij{float(a * spacing), float(b * spacing), float(depth)};
                    kernelSum += c.poly6.value(lengthSquared(rij));
                    gradientSum -= c.spiky.gradient(rij, length(rij)).z;  // component into the wall
                }
        }
        table.kernelSum[sample] = static_cast<float>(kernelSum);
        table.gradientSum[sample] = static_cast<float>(gradientSum);
    }
    return table;
}

}  // namespace

SolverConstants SolverConstants::from(const SimulationParams& params) {
    SolverConstants c;
    c.h = params.kernelRadius();
    c.restDensity = params.fluid.restDensity;
    c.inverseRestDensity = 1.0f / c.restDensity;
    c.poly6 = Poly6Kernel::withRadius(c.h);
    c.spiky = SpikyKernel::withRadius(c.h);

    // Sum the kernels over the rest lattice (cubic, spacing 2r) seen by one
    // interior particle. The mass is chosen so that this lattice has exactly
    // rest density, so a resting block starts with zero constraint error.
    const double d = params.particleSpacing();
    const int reach = static_cast<int>(std::ceil(c.h / d));
    double kernelSum = 0.0;
    double gradientSquaredSum = 0.0;
    for (int a = -reach; a <= reach; ++a)
        for (int b = -reach; b <= reach; ++b)
            for (int k = -reach; k <= reach; ++k) {
                const Vec3 r{float(a * d), float(b * d), float(k * d)};
                kernelSum += c.poly6.value(lengthSquared(r));
                gradientSquaredSum += lengthSquared(c.spiky.gradient(r, length(r)));
            }
    c.particleMass = static_cast<float>(c.restDensity / kernelSum);
    const double gradScale = c.particleMass / double(c.restDensity);
    // sum_k |grad_k C_i|^2 = |sum_j grad W|^2 + sum_j |grad W|^2, scaled by (m/rho0)^2;
    // the first term vanishes on a symmetric lattice.
    c.restGradientSum = static_cast<float>(gradScale * gradScale * gradientSquaredSum);

    const SolverParams& s = params.solver;
    // Units trap (DESIGN.md): the paper's epsilon and s_corr k are relative to
    // the constraint's natural scale; multiply / divide by restGradientSum.
    c.relaxationEpsilon = s.relaxation * c.restGradientSum;
    c.scorrScale = -s.artificialPressure.k / c.restGradientSum;
    const float dq = s.artificialPressure.dq * c.h;
    c.scorrInverseWdq = 1.0f / c.poly6.value(dq * dq);
    c.scorrExponent = s.artificialPressure.n;

    const float r = params.particleRadius;
    c.domain = params.domain;
    c.collisionBox = {params.domain.min + Vec3{r, r, r}, params.domain.max - Vec3{r, r, r}};
    c.wall = makeWallTable(c, params.particleRadius, params.particleSpacing());
    return c;
}

Solver::Solver(const SimulationParams& params, std::shared_ptr<const SolidSet> solids,
               std::uint32_t compactListSpan)
    : params_(params),
      constants_(SolverConstants::from(params)),
      solids_(solids && !solids->empty() ? std::move(solids) : nullptr),
      search_(params.domain, params.kernelRadius(), kMaxGridCells, compactListSpan) {}

void Solver::setParams(const SimulationParams& params) {
    if (!(params.domain == params_.domain) || params.particleRadius != params_.particleRadius ||
        params.solver.kernelRadiusFactor != params_.solver.kernelRadiusFactor)
        throw std::invalid_argument("Solver::setParams cannot change domain or particle size");
    params_ = params;
    constants_ = SolverConstants::from(params);
}

void Solver::ensureCapacity(std::size_t n) {
    if (packed_.size() == n) return;
    packed_.resize(n);
    packedWithLambda_.resize(n);
    if (params_.fluid.vorticity > 0.0f) vorticity_.resize(n);
}

void Solver::step(ParticleStore& p, float dt) {
    const std::size_t n = p.size();
    ensureCapacity(n);
    const SolverConstants& c = constants_;
    const Aabb& box = c.collisionBox;
    const auto stepStart = Clock::now();

    auto t = Clock::now();
    detail::parallelFor(n, [&](std::size_t b, std::size_t e) {
        stages::predictPositions(params_.gravity, dt, box, p.position, p.velocity, p.predicted, b,
                                 e);
    });
    const SolidSet* solids = solids_.get();
    const float radius = params_.particleRadius;
    if (solids) {
        detail::parallelFor(n, [&](std::size_t b, std::size_t e) {
            stages::resolveSolidCollisions(c, *solids, radius, p.position, p.predicted, b, e);
        });
    }
    times_.predict = millisecondsSince(t);

    t = Clock::now();
    search_.sortByCell(p.predicted, perm_);
    times_.gridBuild = millisecondsSince(t);
    auto part = Clock::now();
    p.reorder(perm_);
    times_.reorder = millisecondsSince(part);
    part = Clock::now();
    search_.buildNeighborLists(p.predicted);
    times_.neighborLists = millisecondsSince(part);
    times_.neighborSearch = millisecondsSince(t);

    t = Clock::now();
    float* density = p.density.data();
    PackedPoint* predicted = packed_.data();
    PackedPoint* withLambda = packedWithLambda_.data();
    detail::parallelFor(n, [&](std::size_t b, std::size_t e) {
        stages::packPositions(p.predicted, predicted, b, e);
    });
    times_.lambda = times_.deltaP = 0.0;
    for (int iteration = 0; iteration < params_.solver.iterations; ++iteration) {
        part = Clock::now();
        detail::parallelFor(n, [&](std::size_t b, std::size_t e) {
            stages::computeDensityAndLambda(c, solids, search_, predicted, density, withLambda, b,
                                            e);
        });
        times_.lambda += millisecondsSince(part);
        part = Clock::now();
        // Reads (x*, lambda) of the neighbours, writes the corrected x* over
        // the previous iteration's: the next density pass reads it.
        detail::parallelFor(n, [&](std::size_t b, std::size_t e) {
            stages::correctPositions(c, solids, radius, search_, p.position, withLambda, predicted,
                                     b, e);
        });
        times_.deltaP += millisecondsSince(part);
    }
    detail::parallelFor(n, [&](std::size_t b, std::size_t e) {
        stages::unpackPositions(predicted, p.predicted, b, e);
    });
    times_.solve = millisecondsSince(t);

    t = Clock::now();
    const FluidParams& fluid = params_.fluid;
    const SolverParams& s = params_.solver;
    // x* is still packed in `predicted`; (v, rho) go to the other buffer.
    PackedPoint* velocityDensity = withLambda;
    detail::parallelFor(n, [&](std::size_t b, std::size_t e) {
        stages::updateVelocity(1.0f / dt, p.position, p.predicted, density, p.velocity,
                               velocityDensity, b, e);
    });
    const bool withVorticity = fluid.vorticity > 0.0f;
    if (withVorticity) vorticity_.resize(n);  // allocates once, when first switched on
    if (fluid.viscosity > 0.0f || withVorticity) {
        detail::parallelFor(n, [&](std::size_t b, std::size_t e) {
            stages::applyViscosityAndComputeVorticity(
                c, fluid.viscosity, search_, predicted, velocityDensity,
                withVorticity ? &vorticity_ : nullptr, p.velocity, b, e);
        });
    }
    if (withVorticity) {
        detail::parallelFor(n, [&](std::size_t b, std::size_t e) {
            stages::applyVorticityConfinement(c, fluid.vorticity, dt, search_, p.predicted,
                                              vorticity_, density, p.velocity, b, e);
        });
    }
    detail::parallelFor(n, [&](std::size_t b, std::size_t e) {
        stages::respondToWalls(box, s.restitution, s.friction, p.predicted, p.velocity, b, e);
        if (solids)
            stages::respondToSolids(*solids, radius, s.restitution, s.friction, p.predicted,
                                    p.velocity, b, e);
        stages::commitPositions(p.predicted, p.position, b, e);
    });
    times_.postProcess = millisecondsSince(t);
    times_.total = millisecondsSince(stepStart);
}

std::size_t Solver::memoryBytes() const {
    return search_.memoryBytes() + sizeof(std::uint32_t) * perm_.capacity() +
           sizeof(PackedPoint) * (packed_.capacity() + packedWithLambda_.capacity()) +
           sizeof(float) * 3 * vorticity_.x.capacity();
}

StageTimes& StageTimes::operator+=(const StageTimes& o) {
    predict += o.predict;
    neighborSearch += o.neighborSearch;
    solve += o.solve;
    postProcess += o.postProcess;
    total += o.total;
    gridBuild += o.gridBuild;
    reorder += o.reorder;
    neighborLists += o.neighborLists;
    lambda += o.lambda;
    deltaP += o.deltaP;
    return *this;
}

StageTimes StageTimes::operator*(double factor) const {
    StageTimes r;
    r.predict = predict * factor;
    r.neighborSearch = neighborSearch * factor;
    r.solve = solve * factor;
    r.postProcess = postProcess * factor;
    r.total = total * factor;
    r.gridBuild = gridBuild * factor;
    r.reorder = reorder * factor;
    r.neighborLists = neighborLists * factor;
    r.lambda = lambda * factor;
    r.deltaP = deltaP * factor;
    return r;
}

float maxSpeed(const ParticleStore& p) {
    const std::ptrdiff_t n = static_cast<std::ptrdiff_t>(p.size());
    float maxSquared = 0.0f;
    // max is order-independent, so this reduction is deterministic.
#pragma omp parallel for reduction(max : maxSquared) num_threads(threadCount()) schedule(static)
    for (std::ptrdiff_t i = 0; i < n; ++i)
        maxSquared = std::max(maxSquared, lengthSquared(p.velocity.get(i)));
    return std::sqrt(maxSquared);
}

}  // namespace pbf
