// The one list of per-particle fields.
//
// Every field a particle carries is listed here once, in the style of
// MuJoCo's mjxmacro.h: the list is an X-macro, and everything that must
// touch every field expands it instead of naming the fields by hand — the
// store's members, resize / reserve / reorder / keepRange / memory figures
// (ParticleStore), checkpoints (io/checkpoint.cpp), the records that carry
// particles between MPI ranks (backend/mpi/particle_record.hpp), and the
// arrays of a device backend. Adding a field is one line here; the tests
// in tests/core/particle_fields_test.cpp build the whole list with an extra
// field (PBF_EXTRA_PARTICLE_FIELDS) and check that it reaches each of them.
//
// X(name, type, components, unit, kind, description)
//   name        the member of ParticleStore (a Float3Array for 3 components,
//               a std::vector<type> for 1)
//   type        the component type: float or an unsigned integer (id: 64-bit)
//   components  1 or 3
//   unit        SI unit ("" for none)
//   kind        Saved     state of the simulation: checkpointed, moved with the
//                         particle between MPI ranks, permuted by reorder
//               Working   the solver's working copy: permuted and moved with the
//                         particle during a step, not checkpointed (rebuilt
//                         from the saved fields on restore)
//               Optional  state kept only while a feature needs it: empty while
//                         it is off (added particles get zeros while it is on),
//                         checkpointed as it is (empty or whole)
//   description one line for docs and error messages
#pragma once

#include <cstdint>

#define PBF_PARTICLE_FIELDS(X)                                                              \
    X(position, float, 3, "m", Saved, "position x")                                         \
    X(predicted, float, 3, "m", Working,                                                    \
      "predicted position x*, the solver's working positions (equal to x between steps)")   \
    X(velocity, float, 3, "m/s", Saved, "velocity v")                                       \
    X(density, float, 1, "kg/m^3", Saved, "last density estimate")                          \
    X(id, std::uint64_t, 1, "", Saved, "stable identity, 0-based")                          \
    X(solveAcceleration, float, 3, "m/s^2", Optional,                                       \
      "the last substep's pressure acceleration (its position correction per dt^2), which " \
      "warm-starts the next one (solver.warm_start; empty while it is off)")                \
    PBF_EXTRA_PARTICLE_FIELDS(X)

// Fields a test build adds to the list (see the comment above); empty in pbf.
#ifndef PBF_EXTRA_PARTICLE_FIELDS
#define PBF_EXTRA_PARTICLE_FIELDS(X)
#endif

namespace pbf {

enum class ParticleFieldKind { Saved, Working, Optional };

// The fields by name, in list order (ParticleField::solveAcceleration).
enum class ParticleField {
#define PBF_FIELD_ENUMERATOR(name, type, components, unit, kind, description) name,
    PBF_PARTICLE_FIELDS(PBF_FIELD_ENUMERATOR)
#undef PBF_FIELD_ENUMERATOR
        Count
};

// A field's entry of the list, as data.
struct ParticleFieldInfo {
    const char* name;
    const char* unit;
    int components;
    ParticleFieldKind kind;
    const char* description;
};

}  // namespace pbf
