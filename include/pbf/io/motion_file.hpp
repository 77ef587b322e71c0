// A prescribed motion's keyframes from a CSV file (docs/scenes.md, "Moving
// solids"): a header naming the columns time, x, y, z and optionally rx,
// ry, rz (Euler degrees), in any order, then one keyframe per line.
#pragma once

#include <string>
#include <vector>

#include "pbf/geometry/prescribed_motion.hpp"

namespace pbf {

// Throws SceneError naming `field`, the file, the line and the column.
std::vector<MotionKey> readMotionCsv(const std::string& path, const std::string& field);

}  // namespace pbf
