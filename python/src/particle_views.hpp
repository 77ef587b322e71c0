// numpy views of a World's id-ordered particle arrays (World::arraysById):
// no copy, and writes to positions / velocities reach the solver at the
// next step. Each array's base is a capsule holding a shared_ptr to the
// buffer, so a view stays valid (though detached) after the World replaced
// its buffers (the particle count changed) or was destroyed.
#pragma once

#include <pybind11/numpy.h>

#include "pbf/world/world.hpp"

namespace pbf::python {

pybind11::array positionsView(const ParticleArrays& arrays);   // (N, 3) float32, writable
pybind11::array velocitiesView(const ParticleArrays& arrays);  // (N, 3) float32, writable
pybind11::array densitiesView(const ParticleArrays& arrays);   // (N,) float32, read-only
pybind11::array idsView(const ParticleArrays& arrays);         // (N,) uint64, read-only

}  // namespace pbf::python
