#include "viewer_panel.hpp"

#include <imgui.h>

#include <algorithm>
#include <cstdio>
#include <string>

namespace pbf::render {
namespace {

ImU32 mapColor(float t) {
    const auto c = colorMap(t);
    return ImGui::ColorConvertFloat4ToU32(ImVec4(c[0], c[1], c[2], 1.0f));
}

// A horizontal colour bar with its range under it.
void drawColorBar(const RenderSettings& s) {
    if (s.color == ColorMode::Flat || s.style == Style::Liquid) return;
    const char* unit = s.color == ColorMode::Speed ? "m/s" : "kg/m^3";
    ImGui::Text("%s (%s)", toString(s.color), unit);
    ImDrawList* draw = ImGui::GetWindowDrawList();
    const ImVec2 origin = ImGui::GetCursorScreenPos();
    const float width = ImGui::GetContentRegionAvail().x;
    const float height = 14.0f;
    constexpr int kSegments = 24;
    for (int i = 0; i < kSegments; ++i) {
        const float a = float(i) / kSegments, b = float(i + 1) / kSegments;
        draw->AddRectFilledMultiColor(ImVec2(origin.x + a * width, origin.y),
                                      ImVec2(origin.x + b * width, origin.y + height), mapColor(a),
                                      mapColor(b), mapColor(b), mapColor(a));
    }
    ImGui::Dummy(ImVec2(width, height));
    ImGui::Text("%.3g", double(s.rangeMin));
    char mid[32];
    std::snprintf(mid, sizeof mid, "%.3g", 0.5 * double(s.rangeMin + s.rangeMax));
    ImGui::SameLine(0.5f * (width - ImGui::CalcTextSize(mid).x));
    ImGui::Text("%s", mid);
    char high[32];
    std::snprintf(high, sizeof high, "%.3g", double(s.rangeMax));
    ImGui::SameLine(width - ImGui::CalcTextSize(high).x);
    ImGui::Text("%s", high);
}

void drawControls(PanelState& state, SimulationWorker& worker) {
    if (ImGui::Button(worker.playing() ? "Pause" : "Play", ImVec2(70, 0)))
        worker.setPlaying(!worker.playing());
    ImGui::SameLine();
    if (ImGui::Button("Step")) worker.requestStep();
    ImGui::SameLine();
    if (ImGui::Button("Reset")) worker.requestReset();
    ImGui::SameLine();
    ImGui::TextDisabled("(space, s, r)");

    RenderSettings& s = *state.settings;
    int style = int(s.style);
    ImGui::Combo("look", &style, "spheres\0liquid\0");
    s.style = Style(style);
    int color = int(s.color);
    const ColorMode before = s.color;
    ImGui::Combo("colour", &color, "speed\0density\0flat\0");
    s.color = ColorMode(color);
    if (s.color != before) setDefaultRange(s, state.params);
    if (s.color != ColorMode::Flat)
        ImGui::DragFloatRange2("range", &s.rangeMin, &s.rangeMax, 0.01f);
    if (s.style == Style::Liquid) ImGui::SliderInt("smoothing", &s.smoothingIterations, 0, 10);
    ImGui::Checkbox("domain box", &s.drawBox);
}

void drawSolverParams(PanelState& state, SimulationWorker& worker) {
    if (!ImGui::CollapsingHeader("Solver (live)", ImGuiTreeNodeFlags_DefaultOpen)) return;
    SimulationParams& p = state.params;
    bool changed = false;
    changed |= ImGui::SliderInt("iterations", &p.solver.iterations, 1, 20);
    changed |= ImGui::SliderFloat("CFL", &p.solver.cfl, 0.05f, 1.0f, "%.2f");
    changed |= ImGui::SliderFloat("viscosity", &p.fluid.viscosity, 0.0f, 0.2f, "%.3f");
    changed |= ImGui::SliderFloat("vorticity", &p.fluid.vorticity, 0.0f, 2.0f, "%.3f");
    changed |= ImGui::SliderFloat("s_corr k", &p.solver.artificialPressure.k, 0.0f, 0.5f, "%.3f");
    if (ImGui::Button("Scene values")) {
        p = state.defaults;
        changed = true;
    }
    if (changed) worker.setParams(p);
    if (const std::string error = worker.lastError(); !error.empty())
        ImGui::TextColored(ImVec4(1, 0.4f, 0.3f, 1), "%s", error.c_str());
}

void drawStatistics(const PanelState& state, const SimulationWorker& worker, const Snapshot& snap) {
    if (!ImGui::CollapsingHeader("Statistics", ImGuiTreeNodeFlags_DefaultOpen)) return;
    const FrameReport& r = snap.report;
    ImGui::Text("particles        %zu", r.state.particles);
    ImGui::Text("frame %d   t = %.3f s", r.frame, r.time);
    ImGui::Text("UI               %.0f fps, render %.1f ms", double(state.uiFps), state.renderMs);
    ImGui::Text("simulate frame   %.1f ms (avg %.1f)", snap.frameMs, worker.averageFrameMs());
    ImGui::Text("substeps         %d", r.substeps);
    ImGui::Text("  predict        %.2f ms", r.stageMs.predict);
    ImGui::Text("  neighbours     %.2f ms", r.stageMs.neighborSearch);
    ImGui::Text("  solve          %.2f ms", r.stageMs.solve);
    ImGui::Text("  post-process   %.2f ms", r.stageMs.postProcess);
    ImGui::Text("density error    avg %.2f %%, max %.2f %%", 100.0 * r.state.averageDensityError,
                100.0 * r.state.maxDensityError);
    ImGui::Text("max speed        %.2f m/s", r.state.maxSpeed);
}

}  // namespace

void drawPanel(PanelState& state, SimulationWorker& worker, const Snapshot& snapshot) {
    ImGui::SetNextWindowPos(ImVec2(10, 10), ImGuiCond_FirstUseEver);
    // Narrow, see-through and never taller than the window: the water stays visible.
    ImGui::SetNextWindowSize(ImVec2(300, 0), ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowSizeConstraints(ImVec2(200, 0),
                                        ImVec2(600, ImGui::GetIO().DisplaySize.y - 20.0f));
    ImGui::SetNextWindowBgAlpha(0.7f);
    ImGui::Begin("pbf");
    drawControls(state, worker);
    drawColorBar(*state.settings);
    drawSolverParams(state, worker);
    drawStatistics(state, worker, snapshot);
    ImGui::TextDisabled("left drag: orbit  right drag: pan  wheel: zoom");
    ImGui::End();
}

}  // namespace pbf::render
