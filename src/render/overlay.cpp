#include "pbf/render/overlay.hpp"

#include <backends/imgui_impl_opengl3.h>
#include <epoxy/gl.h>
#include <imgui.h>

#include <stdexcept>

#include "color_bar.hpp"

namespace pbf::render {

// An ImGui context of its own (no platform backend: the display size and
// time step are set by hand), so the overlay also works beside a viewer.
struct ColorBarOverlay::Impl {
    ImGuiContext* context = nullptr;
};

ColorBarOverlay::ColorBarOverlay() : impl_(std::make_unique<Impl>()) {
    ImGuiContext* previous = ImGui::GetCurrentContext();
    impl_->context = ImGui::CreateContext();
    ImGui::SetCurrentContext(impl_->context);
    ImGui::GetIO().IniFilename = nullptr;
    ImGui::StyleColorsDark();
    const bool ok = ImGui_ImplOpenGL3_Init("#version 330 core");
    ImGui::SetCurrentContext(previous);
    if (!ok) {
        ImGui::DestroyContext(impl_->context);
        throw std::runtime_error(
            "cannot initialise Dear ImGui's OpenGL 3 backend for the colour bar");
    }
}

ColorBarOverlay::~ColorBarOverlay() {
    ImGuiContext* previous = ImGui::GetCurrentContext();
    ImGui::SetCurrentContext(impl_->context);
    ImGui_ImplOpenGL3_Shutdown();
    ImGui::DestroyContext(impl_->context);
    ImGui::SetCurrentContext(previous == impl_->context ? nullptr : previous);
}

void ColorBarOverlay::draw(unsigned framebuffer, int width, int height,
                           const RenderSettings& settings) {
    if (settings.color == ColorMode::Flat || settings.style == Style::Liquid) return;
    ImGuiContext* previous = ImGui::GetCurrentContext();
    ImGui::SetCurrentContext(impl_->context);
    ImGuiIO& io = ImGui::GetIO();
    io.DisplaySize = ImVec2(float(width), float(height));
    io.DeltaTime = 1.0f / 30.0f;
    // Twice: a window's first frame only measures its size (ImGui draws it from the second).
    for (int pass = 0; pass < 2; ++pass) {
        ImGui_ImplOpenGL3_NewFrame();
        ImGui::NewFrame();
        const float barWidth = width < 400 ? float(width) * 0.45f : 220.0f;
        ImGui::SetNextWindowPos(ImVec2(8, 8));
        ImGui::SetNextWindowSize(ImVec2(barWidth, 0));
        ImGui::SetNextWindowBgAlpha(0.55f);
        ImGui::Begin("colour bar", nullptr,
                     ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_NoInputs |
                         ImGuiWindowFlags_NoSavedSettings);
        drawColorBar(settings);
        ImGui::End();
        ImGui::Render();
    }
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer);
    glViewport(0, 0, width, height);
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    ImGui::SetCurrentContext(previous);
}

}  // namespace pbf::render
