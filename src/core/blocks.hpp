// The fixed blocks of particle indices that the parallel loops hand to one
// thread at a time (private header). Deterministic reductions (parallel.hpp,
// reactions.hpp) sum per block and then in block order.
#pragma once

#include <cstddef>

namespace pbf::detail {

// Particles per work item: large enough to amortise scheduling, small enough
// to balance two threads on a few thousand particles.
inline constexpr std::size_t kBlockSize = 1024;

}  // namespace pbf::detail
