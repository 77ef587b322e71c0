// SIMD constants shared by every instruction set target (simd-inl.h holds
// the per-target helpers). Private header.
#pragma once

#include <cstddef>

namespace pbf::simd {

// Entries a list may be over-read by: list buffers keep this much slack.
inline constexpr std::size_t kMaxLanes = 64;

}  // namespace pbf::simd
