// The reference backend (private header): plain scalar C++, one short
// function per equation of Macklin & Mueller 2013 (equations.hpp), clarity
// over speed. It is the oracle the SIMD backend is tested against
// (tests/backend/reference/) and the readable version of Algorithm 1: its
// step() lists the stages by name, one member function each.
//
// Same stages in the same order as the CPU backend (backend/cpu/solver.cpp),
// with the same boundary terms (backend/boundary.hpp), but serial, without
// reordering the particles, with its own neighbour search
// (neighbor_grid.hpp) and the particles as arrays of Vec3.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "backend/host_backend.hpp"
#include "backend/reference/neighbor_grid.hpp"
#include "backend/step_terms.hpp"

namespace pbf {

class ReferenceBackend final : public HostBackend {
  public:
    explicit ReferenceBackend(const SimulationParams& params);

    BackendKind kind() const override { return BackendKind::Reference; }
    void step(const SolverContext& context, float dt) override;
    BackendDiagnostics diagnostics() const override;

  private:
    // The step's constant inputs and the terms they switch on, given to
    // every stage.
    struct Step {
        const SimulationParams& params;
        const SolverConstants& c;
        StepTerms terms;
        const SolidSet* solids;  // null when there are none
        float dt;
        ReactionAccumulator* reactions;  // null when no solid is coupled
    };
    // The stages of step(), in the order of the Stage list
    // (backend/step_plan.hpp); reference_backend.cpp says what each does.
    void predict(const Step& s);
    void findNeighbors();
    std::int64_t densityAndLambda(const Step& s);  // the sum of C_i, fixed point
    void correctPositions(const Step& s);
    void recordSolveAcceleration(const Step& s);
    void updateVelocity(const Step& s);
    void viscosityAndVorticity(const Step& s);
    void physicalViscosity(const Step& s);
    void vorticityConfinement(const Step& s);
    void surfaceTension(const Step& s);
    void colourGradient(const Step& s);
    void bandNormal(const Step& s);
    void curvature(const Step& s);
    void curvatureForce(const Step& s);
    void boundaryResponse(const Step& s);

    void load();                  // store_ -> the Vec3 arrays
    void commit(bool warmStart);  // the Vec3 arrays -> store_
    std::size_t bufferBytes() const;

    reference::NeighborGrid grid_;
    // Working copies of the state, one Vec3 per particle, in store_'s order.
    std::vector<Vec3> position_;   // x, the start of the step
    std::vector<Vec3> predicted_;  // x*
    std::vector<Vec3> corrected_;  // x* + dp of the current iteration (Jacobi)
    std::vector<Vec3> velocity_;
    std::vector<Vec3> postVelocity_;           // v after XSPH and confinement (Jacobi)
    std::vector<Vec3> vorticity_;              // omega, eq. 15
    std::vector<Vec3> predictedVelocity_;      // v + dt g, before the iterations
    std::vector<Vec3> solveAcceleration_;      // warm start: the last substep's, then this one's
    std::vector<Vec3> viscosityAcceleration_;  // physical viscosity: nu lap v of this substep
    std::vector<float> surfaceLayer_;          // s_i, the surface layer's weights (cohesion)
    std::vector<Vec3> colourGradient_;         // g_i of the curvature force
    std::vector<Vec3> bandNormal_;             // nb_i
    std::vector<float> curvature_;             // kappa_i
    std::vector<float> density_;
    std::vector<float> lambda_;
};

std::unique_ptr<Backend> makeReferenceBackend(const SimulationParams& params);

}  // namespace pbf
