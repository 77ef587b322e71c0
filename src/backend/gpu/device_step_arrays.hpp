// The GPU backend's per-particle step arrays (private header): the scratch
// it keeps beside the particle fields, each with the setting that needs it.
// One list, as the particle fields' (include/pbf/core/particle_fields.hpp):
// DeviceBackend declares, sizes and counts its members from it
// (device_backend_impl.hpp), and the memory table that refuses a scene too
// large for the device sums it (device_memory.cpp), so the two cannot drift.
//
// X(name, type, components, use)
//   name        the member (name_): three float arrays for 3 components, one array for 1
//   type        the element type
//   components  1 or 3
//   use         when it is allocated (StepArrayUse)
#pragma once

#include <cstdint>

#include "backend/step_terms.hpp"

#define PBF_DEVICE_STEP_ARRAYS(X)                                                                  \
    X(corrected, float, 3, Always)                     /* the correction pass's output (Jacobi) */ \
    X(lambda, float, 1, Always)                        /* the constraint's multipliers */          \
    X(post, float, 3, PostProcess)                     /* v after XSPH and confinement (Jacobi) */ \
    X(vorticity, float, 3, Vorticity)                  /* omega */                                 \
    X(surfaceLayer, float, 1, Cohesion)                /* the surface layer's weights s */         \
    X(colourGradient, float, 3, SurfaceTension)        /* the curvature force's g */               \
    X(bandNormal, float, 3, SurfaceTension)            /* its band normals nb */                   \
    X(curvature, float, 1, SurfaceTension)             /* its kappa */                             \
    X(reactionSolid0, std::uint32_t, 1, CoupledSolids) /* reaction records, slot 0: */             \
    X(reactionAt0, float, 3, CoupledSolids)            /* the solid, where, the move */            \
    X(reactionMove0, float, 3, CoupledSolids)                                                      \
    X(reactionSolid1, std::uint32_t, 1, CoupledSolids) /* slot 1 */                                \
    X(reactionAt1, float, 3, CoupledSolids)                                                        \
    X(reactionMove1, float, 3, CoupledSolids)

namespace pbf::gpu {

enum class StepArrayUse {
    Always,
    PostProcess,     // XSPH, vorticity confinement or the physical viscosity on
    Vorticity,       // vorticity confinement on
    Cohesion,        // surface tension's cohesion on (fluid.surface_tension > 0)
    SurfaceTension,  // the curvature force on (fluid.surface_tension > 0)
    CoupledSolids,   // a solid that takes the fluid's reaction (a rigid body)
};

inline bool stepArrayInUse(StepArrayUse use, const StepTerms& terms, bool coupledSolids) {
    switch (use) {
        case StepArrayUse::Always:
            return true;
        case StepArrayUse::PostProcess:
            return terms.velocityPostProcess();
        case StepArrayUse::Vorticity:
            return terms.vorticity;
        case StepArrayUse::Cohesion:
            return terms.cohesion;
        case StepArrayUse::SurfaceTension:
            return terms.curvature;
        case StepArrayUse::CoupledSolids:
            return coupledSolids;
    }
    return true;
}

}  // namespace pbf::gpu
