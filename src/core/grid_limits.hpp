// Limits every backend's uniform grid shares (private header): the
// parameters are validated against them (core/params.cpp) and the
// neighbour searches are sized by them.
#pragma once

#include <cstddef>

namespace pbf {

// Largest grid pbf builds (cells of edge h over the domain): 2^26 cells,
// about 0.5 GiB of cell tables. Scenes beyond it are refused when loaded.
inline constexpr std::size_t kMaxGridCells = std::size_t{1} << 26;

}  // namespace pbf
