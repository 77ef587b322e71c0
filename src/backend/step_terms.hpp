// The optional terms of a solver step, decided once per step (private
// header, shared by the backends), in the manner of Box2D v3's
// b2StepContext: the CPU solver's plan, the MPI backend's exchanges, the
// GPU backend's plan and array sizing and the reference backend's step all
// read these flags instead of testing the settings themselves, so that a
// term is on in every backend under the same condition.
#pragma once

#include <functional>

#include "core/iteration_control.hpp"
#include "pbf/backend/backend.hpp"
#include "pbf/core/config.hpp"
#include "pbf/core/params.hpp"
#include "pbf/core/solver_constants.hpp"
#include "pbf/geometry/solids.hpp"

namespace pbf {

struct StepTerms {
    bool warmStart = false;          // solver.warm_start > 0: x* += w dt^2 a, a recorded after
    bool xsph = false;               // fluid.viscosity > 0: XSPH viscosity (paper eq. 17)
    bool vorticity = false;          // fluid.vorticity > 0: omega_i, confinement (eq. 15-16)
    bool physicalViscosity = false;  // fluid.kinematic_viscosity > 0: v += dt nu lap v
    bool cohesion = false;           // surface tension's cohesion and adhesion
    bool curvature = false;          // surface tension's curvature force
    bool solids = false;             // the scene has solids
    bool errorControlled = false;    // iterations until solver.max_density_error is met

    // XSPH's neighbour pass, which also computes omega_i.
    PBF_HD bool viscosityPass() const { return xsph || vorticity; }
    // Any pass after the velocity update that reads the neighbours' velocities.
    PBF_HD bool velocityPostProcess() const { return viscosityPass() || physicalViscosity; }
};

// The solids a step sees: null when there are none.
inline const SolidSet* presentSolids(const SolidSet* solids) {
    return solids && !solids->empty() ? solids : nullptr;
}

// The terms of a step with these settings and constants (the constants
// carry surface tension's scales, zero while it is off).
inline StepTerms stepTerms(const SimulationParams& params, const SolverConstants& constants,
                           bool solids) {
    StepTerms t;
    t.warmStart = params.solver.warmStart > 0.0f;
    t.xsph = params.fluid.viscosity > 0.0f;
    t.vorticity = params.fluid.vorticity > 0.0f;
    t.physicalViscosity = params.fluid.kinematicViscosity > 0.0f;
    t.cohesion = constants.cohesionScale > 0.0f;
    t.curvature = constants.surfaceTension > 0.0f;
    t.solids = solids;
    t.errorControlled = IterationControl(params.solver).errorControlled();
    return t;
}

inline StepTerms stepTerms(const SolverContext& context) {
    return stepTerms(context.params, context.constants, presentSolids(context.solids) != nullptr);
}

// A plan's `enabled` test for a stage that runs while `term` (a flag of
// StepTerms, or one of its tests) is on: whenOn(&StepTerms::warmStart). The
// step context it is given has the step's terms as `terms`.
template <class Term>
auto whenOn(Term term) {
    return [term](const auto& s) { return std::invoke(term, s.terms); };
}

}  // namespace pbf
