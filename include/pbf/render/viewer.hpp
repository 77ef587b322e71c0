// The interactive viewer behind `pbf view`: a GLFW window, the scene
// simulated live on a worker thread, a Dear ImGui panel (play / pause /
// step / reset, live solver parameters, statistics) and an orbit camera.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include "pbf/backend/backend.hpp"
#include "pbf/io/scene.hpp"
#include "pbf/render/camera.hpp"
#include "pbf/render/renderer.hpp"

namespace pbf::render {

struct ViewerOptions {
    int width = 1280;
    int height = 720;
    RenderSettings settings;
    std::optional<Camera> camera;  // default: frameBox(domain)
    bool paused = false;
    // Batch mode (tests, docs): simulate `frames` frames, draw, save the
    // window (panel included) to `screenshot` as PNG and close.
    std::filesystem::path screenshot;
    int frames = 0;
    BackendKind device = BackendKind::Cpu;  // the simulation's solver (--device)
};

struct ViewerSummary {
    int framesSimulated = 0;
    int framesDrawn = 0;
    double averageStepMs = 0.0;    // per simulated frame, on the worker thread
    double averageRenderMs = 0.0;  // per drawn frame, on the UI thread
    std::string error;             // why the simulation stopped (a failed frame), if it did
};

// Throws RenderError when no window can be opened (no display: use `pbf render`).
ViewerSummary runViewer(const Scene& scene, const ViewerOptions& options);

}  // namespace pbf::render
