// The reference backend (private header): plain scalar C++, one short
// function per equation of Macklin & Mueller 2013 (equations.hpp), brute
// clarity over speed. It is the oracle the SIMD backend is tested against.
#pragma once

#include <memory>

#include "pbf/backend.hpp"

namespace pbf {

std::unique_ptr<Backend> makeReferenceBackend(const SimulationParams& params);

}  // namespace pbf
