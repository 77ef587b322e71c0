// The point-cache writer shared by the particle and diffuse caches (private
// header of pbf_surface).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "pbf/io/io.hpp"

namespace pbf::surface::detail {

struct ExtraPointAttributes {
    std::vector<std::pair<std::string, std::vector<float>>> floats;
    std::vector<std::pair<std::string, std::vector<std::int32_t>>> ints;
};

// `frame`'s position, velocity, density and id (those present) plus `extra`,
// as one PointDataGrid named `gridName`. Atomic. Throws IoError.
void writePointsVdb(const std::filesystem::path& path, const ParticleFrame& frame,
                    const std::string& gridName, const ExtraPointAttributes& extra);

}  // namespace pbf::surface::detail
