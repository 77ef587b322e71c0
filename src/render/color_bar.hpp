// A colour bar for the colour map, drawn into the current Dear ImGui window:
// the mode and unit, the ramp, and its low, middle and high values.
#pragma once

#include "pbf/render/renderer.hpp"

namespace pbf::render {

// Draws nothing for flat colours and the liquid look.
void drawColorBar(const RenderSettings& settings);

}  // namespace pbf::render
