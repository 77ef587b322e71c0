// `pbf view`: window, input, and the draw loop. The simulation runs on
// SimulationWorker's thread; this thread only uploads the newest snapshot,
// draws it and the panel, so step time and render time are separate.
#include "pbf/render/viewer.hpp"

#include <epoxy/gl.h>
// epoxy first: GLFW must not include the system GL header.
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <numbers>
#include <string>

#include "pbf/render/headless.hpp"
#include "pbf/render/solid_mesh.hpp"
#include "sim_worker.hpp"
#include "viewer_panel.hpp"

namespace pbf::render {
namespace {

using Clock = std::chrono::steady_clock;

std::string& glfwMessage() {
    static std::string message;
    return message;
}

void onGlfwError(int /*code*/, const char* description) {
    glfwMessage() = description;
}

// Input the callbacks collect between frames.
struct Input {
    double scroll = 0.0;
};

void onScroll(GLFWwindow* window, double /*dx*/, double dy) {
    static_cast<Input*>(glfwGetWindowUserPointer(window))->scroll += dy;
}

[[noreturn]] void noWindow(const std::string& what) {
    const char* display = std::getenv("DISPLAY");
    const std::string reason = glfwMessage().empty() ? what : what + ": " + glfwMessage();
    throw RenderError(
        reason + (display == nullptr || *display == '\0' ? " (DISPLAY is not set)" : "") +
        ". `pbf view` needs a display; without one, use `pbf render SCENE` for PNG frames and "
        "video, or run under xvfb-run");
}

// RAII for GLFW, the window and ImGui, so every exit path cleans up.
struct Window {
    GLFWwindow* handle = nullptr;
    Input input;

    Window(int width, int height, const std::string& title) {
        glfwSetErrorCallback(onGlfwError);
        if (glfwInit() != GLFW_TRUE) noWindow("cannot initialise GLFW");
        glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
        glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
        glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
        glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
        glfwWindowHint(GLFW_SAMPLES, 4);
        handle = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
        if (handle == nullptr) {
            glfwTerminate();
            noWindow("cannot open an OpenGL 3.3 window");
        }
        glfwMakeContextCurrent(handle);
        glfwSwapInterval(1);
        glfwSetWindowUserPointer(handle, &input);
        // Installed before ImGui's backend, which chains to it.
        glfwSetScrollCallback(handle, onScroll);
        IMGUI_CHECKVERSION();
        ImGui::CreateContext();
        ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini in the user's directory
        ImGui::StyleColorsDark();
        ImGui_ImplGlfw_InitForOpenGL(handle, true);
        ImGui_ImplOpenGL3_Init("#version 330 core");
    }
    ~Window() {
        ImGui_ImplOpenGL3_Shutdown();
        ImGui_ImplGlfw_Shutdown();
        ImGui::DestroyContext();
        glfwDestroyWindow(handle);
        glfwTerminate();
    }
    Window(const Window&) = delete;
    Window& operator=(const Window&) = delete;
};

// Mouse and keys -> camera and worker, unless ImGui wants them.
void handleInput(Window& window, OrbitCamera& camera, SimulationWorker& worker, double& lastX,
                 double& lastY) {
    const ImGuiIO& io = ImGui::GetIO();
    double x = 0.0, y = 0.0;
    glfwGetCursorPos(window.handle, &x, &y);
    const float dx = float(x - lastX), dy = float(y - lastY);
    lastX = x;
    lastY = y;
    if (!io.WantCaptureMouse) {
        int width = 1, height = 1;
        glfwGetWindowSize(window.handle, &width, &height);
        if (glfwGetMouseButton(window.handle, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS)
            camera.orbit(-0.3f * dx, 0.3f * dy);
        if (glfwGetMouseButton(window.handle, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS ||
            glfwGetMouseButton(window.handle, GLFW_MOUSE_BUTTON_MIDDLE) == GLFW_PRESS)
            camera.pan(-dx / float(height), dy / float(height));
        if (window.input.scroll != 0.0) camera.zoom(float(std::pow(0.9, window.input.scroll)));
    }
    window.input.scroll = 0.0;
    // ImGui 1.86 indexes keys by the platform backend's codes (GLFW here).
    if (!io.WantCaptureKeyboard) {
        if (ImGui::IsKeyPressed(GLFW_KEY_SPACE, false)) worker.setPlaying(!worker.playing());
        if (ImGui::IsKeyPressed(GLFW_KEY_S, false)) worker.requestStep();
        if (ImGui::IsKeyPressed(GLFW_KEY_R, false)) worker.requestReset();
        if (ImGui::IsKeyPressed(GLFW_KEY_ESCAPE, false))
            glfwSetWindowShouldClose(window.handle, GLFW_TRUE);
    }
}

RenderParticles toRenderParticles(const Snapshot& s, ColorMode mode) {
    RenderParticles out;
    const std::size_t n = s.speed.size();
    out.data.resize(4 * n);
    for (std::size_t i = 0; i < n; ++i) {
        out.data[4 * i + 0] = s.xyz[3 * i + 0];
        out.data[4 * i + 1] = s.xyz[3 * i + 1];
        out.data[4 * i + 2] = s.xyz[3 * i + 2];
        out.data[4 * i + 3] = mode == ColorMode::Density ? s.density[i] : s.speed[i];
    }
    return out;
}

// The panel covers the left kPanelWidth pixels: frame the domain in the
// rest of the window, then pan so that it sits in the middle of that rest.
OrbitCamera defaultViewerCamera(const Aabb& domain, const ViewerOptions& options) {
    if (options.camera) return OrbitCamera(*options.camera);
    constexpr float kPanelWidth = 320.0f;
    const float free = std::max(float(options.width) - kPanelWidth, 0.5f * float(options.width));
    const Camera framed = frameBox(domain, free / float(options.height));
    OrbitCamera camera(framed);
    const float halfHeightAtTarget =
        std::tan(0.5f * framed.fovY * std::numbers::pi_v<float> / 180.0f);
    const float shiftPixels = 0.5f * (float(options.width) - free);
    camera.pan(-shiftPixels / (0.5f * float(options.height)) * halfHeightAtTarget, 0.0f);
    return camera;
}

}  // namespace

ViewerSummary runViewer(const Scene& scene, const ViewerOptions& options) {
    const bool batch = !options.screenshot.empty();
    Window window(options.width, options.height, "pbf view: " + scene.name);
    SceneRenderer renderer;
    renderer.setDomain(scene.simulation.domain);
    renderer.setParticleRadius(scene.simulation.particleRadius);
    const SolidMesh statics = tessellateSolids(scene);
    const std::vector<SolidMesh> bodyShapes = tessellateBodyShapes(scene);
    const std::vector<DrivenShape> driven = tessellateDrivenSolids(scene);
    renderer.setSolids(statics);
    OrbitCamera camera = defaultViewerCamera(scene.simulation.domain, options);

    RenderSettings settings = options.settings;
    PanelState panel;
    panel.settings = &settings;
    panel.params = scene.simulation;
    panel.defaults = scene.simulation;

    SimulationWorker worker(scene, !options.paused && !batch, options.device);
    if (batch) worker.pauseAt(options.frames);

    ViewerSummary summary;
    Snapshot snapshot;
    ColorMode uploadedMode = settings.color;
    double lastX = 0.0, lastY = 0.0;
    glfwGetCursorPos(window.handle, &lastX, &lastY);
    double renderMsTotal = 0.0;
    int settledFrames = 0;  // batch: frames drawn after the simulation reached its frame count
    auto lastFrame = Clock::now();
    while (!glfwWindowShouldClose(window.handle)) {
        // At most ~60 UI frames per second (no vsync under Xvfb or with some
        // drivers): the drawing must not take the simulation's cores.
        const double sinceLast = std::chrono::duration<double>(Clock::now() - lastFrame).count();
        if (sinceLast < 1.0 / 60.0)
            glfwWaitEventsTimeout(1.0 / 60.0 - sinceLast);
        else
            glfwPollEvents();
        const auto t0 = Clock::now();
        panel.uiFps =
            float(1.0 / std::max(1e-6, std::chrono::duration<double>(t0 - lastFrame).count()));
        lastFrame = t0;
        if (worker.takeSnapshot(snapshot) || settings.color != uploadedMode) {
            renderer.upload(toRenderParticles(snapshot, settings.color));
            uploadedMode = settings.color;
            if (!bodyShapes.empty() || !driven.empty()) {  // moving solids at this snapshot
                SolidMesh solids = statics;
                for (std::size_t k = 0; k < bodyShapes.size() && k < snapshot.bodyPoses.size(); ++k)
                    appendPosed(solids, bodyShapes[k], snapshot.bodyPoses[k]);
                appendDriven(solids, driven, snapshot.report.time);
                renderer.setSolids(solids);
            }
        }
        ImGui_ImplOpenGL3_NewFrame();
        ImGui_ImplGlfw_NewFrame();
        ImGui::NewFrame();
        handleInput(window, camera, worker, lastX, lastY);
        drawPanel(panel, worker, snapshot);
        ImGui::Render();

        int width = 0, height = 0;
        glfwGetFramebufferSize(window.handle, &width, &height);
        if (width > 0 && height > 0) {
            renderer.render(0, width, height, camera.camera(), settings);
            ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
        }
        const double renderMs =
            std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
        panel.renderMs = renderMs;
        renderMsTotal += renderMs;
        ++summary.framesDrawn;

        // Batch mode: a few UI frames after the last simulated one let the
        // panel settle its layout; then the back buffer is saved.
        const bool batchDone =
            (snapshot.report.frame >= options.frames || worker.failed()) && !worker.playing();
        if (batch && batchDone && ++settledFrames >= 3) {
            writePng(options.screenshot, readFramebuffer(0, width, height));
            glfwSetWindowShouldClose(window.handle, GLFW_TRUE);
        }
        glfwSwapBuffers(window.handle);
    }
    summary.framesSimulated = worker.framesSimulated();
    if (worker.failed()) summary.error = worker.lastError();
    summary.averageStepMs = worker.averageFrameMs();
    summary.averageRenderMs = summary.framesDrawn > 0 ? renderMsTotal / summary.framesDrawn : 0.0;
    return summary;
}

}  // namespace pbf::render
