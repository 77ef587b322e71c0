// The colour bar, drawn with Dear ImGui (viewer panel and headless overlay).
#include "color_bar.hpp"

#include <imgui.h>

#include <cstdio>

namespace pbf::render {
namespace {

ImU32 mapColor(float t) {
    const auto c = colorMap(t);
    return ImGui::ColorConvertFloat4ToU32(ImVec4(c[0], c[1], c[2], 1.0f));
}

}  // namespace

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

}  // namespace pbf::render
