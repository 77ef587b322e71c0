// The viewer's Dear ImGui panel: controls, live solver parameters,
// statistics and the colour bar.
#pragma once

#include "pbf/core/params.hpp"
#include "pbf/render/renderer.hpp"
#include "sim_worker.hpp"

namespace pbf::render {

struct PanelState {
    RenderSettings* settings = nullptr;
    SimulationParams params;  // what the sliders edit
    SimulationParams defaults;
    float uiFps = 0.0f;
    double renderMs = 0.0;  // UI thread: scene + panel
    double uploadMs = 0.0;
};

// Draws the panel; changes go to the worker (play, step, reset, parameters).
void drawPanel(PanelState& state, SimulationWorker& worker, const Snapshot& snapshot);

}  // namespace pbf::render
