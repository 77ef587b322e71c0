#include "viewer_panel.hpp"

#include <imgui.h>

#include <algorithm>
#include <cstdio>
#include <string>

#include "color_bar.hpp"

namespace pbf::render {
namespace {

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
    ImGui::Text("    grid %.2f, reorder %.2f, lists %.2f", r.stageMs.gridBuild, r.stageMs.reorder,
                r.stageMs.neighborLists);
    ImGui::Text("  solve          %.2f ms", r.stageMs.solve);
    ImGui::Text("    lambda %.2f, delta-p %.2f", r.stageMs.lambda, r.stageMs.deltaP);
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
