// The ImGui panels of the viewer.
#include "viewer/app/panels.hpp"

#include <imgui.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <filesystem>
#include <vector>

#include "render/backend.hpp"
#include "render/colour_modes.hpp"

namespace lidarscout::viewer::app {
namespace {

bool contains_ci(const std::string& text, const std::string& needle) {
    const auto it = std::search(text.begin(), text.end(), needle.begin(), needle.end(),
                                [](char a, char b) { return std::tolower(a) == std::tolower(b); });
    return it != text.end();
}

void progress_line(const char* label, StageProgress p) {
    const float f = p.total ? static_cast<float>(static_cast<double>(p.done) / p.total) : 1.0f;
    char text[96];
    std::snprintf(text, sizeof text, "%llu / %llu", (unsigned long long)p.done, (unsigned long long)p.total);
    ImGui::ProgressBar(f, ImVec2(-140, 0), text);
    ImGui::SameLine();
    ImGui::TextUnformatted(label);
}

void tiles_panel(const dataset::Dataset& ds, PanelState& state, PanelActions& actions) {
    ImGui::SetNextWindowPos(ImVec2(10, 10), ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowSize(ImVec2(300, 260), ImGuiCond_FirstUseEver);
    if (!ImGui::Begin("Tiles")) return ImGui::End();
    char buffer[256];
    std::snprintf(buffer, sizeof buffer, "%s", state.filter.c_str());
    if (ImGui::InputText("filter", buffer, sizeof buffer)) state.filter = buffer;
    std::vector<std::uint32_t> shown;
    std::vector<std::string> names(ds.tiles.size());
    for (std::uint32_t i = 0; i < ds.tiles.size(); ++i) {
        names[i] = std::filesystem::path(ds.tiles[i].tile.path).filename().string();
        if (state.filter.empty() || contains_ci(names[i], state.filter)) shown.push_back(i);
    }
    ImGui::Text("%zu of %zu tiles (double-click: fly there)", shown.size(), ds.tiles.size());
    ImGui::BeginChild("list");
    ImGuiListClipper clipper;
    clipper.Begin(static_cast<int>(shown.size()));
    while (clipper.Step()) {
        for (int k = clipper.DisplayStart; k < clipper.DisplayEnd; ++k) {
            const std::uint32_t i = shown[k];
            ImGui::PushID(static_cast<int>(i));
            if (ImGui::Selectable(names[i].c_str(), state.selected == i, ImGuiSelectableFlags_AllowDoubleClick)) {
                state.selected = i;
                if (ImGui::IsMouseDoubleClicked(0)) actions.fly_to = i;
            }
            ImGui::PopID();
        }
    }
    ImGui::EndChild();
    ImGui::End();
}

void stats_panel(const dataset::Dataset& ds, const SchedulerStats& s, double frame_ms, const PanelState& state) {
    ImGui::SetNextWindowPos(ImVec2(10, 280), ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowSize(ImVec2(420, 300), ImGuiCond_FirstUseEver);
    if (!ImGui::Begin("Stats and progress")) return ImGui::End();
    ImGui::Text("tiles %zu (%zu skipped), %.2f G points", s.tiles, ds.skipped.size(), ds.point_count / 1e9);
    ImGui::Text("chunk points %llu", (unsigned long long)s.chunk_points_loaded);
    ImGui::Text("patches with heightmaps: %zu linear, %zu network", s.heightmaps_linear, s.heightmaps_cnn);
    ImGui::Text("full-res: %zu tiles, %.1f M points, %zu released", s.full_res_tiles, s.full_res_points / 1e6,
                s.full_res_released);
    ImGui::Text("coarse levels kept: %zu tiles; LOD %.1f M points", s.coarse_tiles, s.lod_points / 1e6);
    ImGui::Text("memory %.0f / %.0f MiB (peak %.0f)", s.bytes_used / 1048576.0, s.memory_budget / 1048576.0,
                s.peak_bytes_used / 1048576.0);
    ImGui::Text("frame %.1f ms (%.1f fps)", frame_ms, frame_ms > 0 ? 1000.0 / frame_ms : 0.0);
    if (!state.cursor.empty()) ImGui::Text("cursor %s", state.cursor.c_str());
    ImGui::Separator();
    progress_line("tiles (chunk points)", s.tiles_loaded);
    progress_line("chunk points", s.chunk_points);
    progress_line("heightmaps (linear)", s.linear);
    if (s.cnn.total) progress_line("heightmaps (network)", s.cnn);
    progress_line("full-res tiles in view", s.full_res);
    for (const auto& note : s.notes) ImGui::TextWrapped("%s", note.c_str());
    if (s.errors) ImGui::Text("%zu errors (files that could not be read)", s.errors);
    if (!state.status.empty()) ImGui::TextWrapped("%s", state.status.c_str());
    ImGui::End();
}

void settings_panel(ViewSettings& v, PanelActions& actions) {
    ImGui::SetNextWindowPos(ImVec2(10, 590), ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowSize(ImVec2(320, 270), ImGuiCond_FirstUseEver);
    if (!ImGui::Begin("Settings")) return ImGui::End();
    if (ImGui::InputInt("memory MiB", &v.budget_mb, 256, 1024, ImGuiInputTextFlags_EnterReturnsTrue)) {
        v.budget_mb = std::max(64, v.budget_mb);
        actions.budget_changed = true;
    }
    ImGui::SliderInt("point size", &v.style.point_size, 1, 8);
    ImGui::SliderInt("chunk point size", &v.style.chunk_point_size, 1, 8);
    static constexpr std::array<render::ColourMode, 4> kModes = {render::ColourMode::Rgb, render::ColourMode::Elevation,
                                                                 render::ColourMode::Intensity,
                                                                 render::ColourMode::Classification};
    if (ImGui::BeginCombo("colour", std::string(render::colour_mode_name(v.style.colour.mode)).c_str())) {
        for (const auto m : kModes) {
            if (ImGui::Selectable(std::string(render::colour_mode_name(m)).c_str(), m == v.style.colour.mode)) {
                v.style.colour.mode = m;
            }
        }
        ImGui::EndCombo();
    }
    ImGui::SliderFloat("EDL", &v.style.resolve.edl_strength, 0.0f, 3.0f);
    const std::string device = v.style.backend == render::Backend::Cuda ? " (" + render::cuda_device_name() + ")" : "";
    ImGui::Text("rasterizer: %s%s", std::string(render::backend_name(v.style.backend)).c_str(), device.c_str());
    ImGui::SliderFloat("render scale", &v.render_scale, 0.25f, 1.0f);
    ImGui::Checkbox("chunk points", &v.layers.chunk_points);
    ImGui::SameLine();
    ImGui::Checkbox("heightmaps", &v.layers.heightmaps);
    ImGui::Checkbox("full-res", &v.layers.full_points);
    ImGui::SameLine();
    ImGui::Checkbox("tile boxes", &v.tile_boxes);
    if (ImGui::Button("screenshot (F12)")) actions.screenshot = true;
    ImGui::TextWrapped("left drag: orbit, right drag: pan, wheel: zoom, WASD/QE: fly (shift: faster); "
                       "drop a folder or files to open them");
    ImGui::End();
}

}  // namespace

PanelActions draw_panels(const dataset::Dataset& dataset, const SchedulerStats& stats, double frame_ms,
                         ViewSettings& settings, PanelState& state) {
    PanelActions actions;
    tiles_panel(dataset, state, actions);
    stats_panel(dataset, stats, frame_ms, state);
    settings_panel(settings, actions);
    return actions;
}

}  // namespace lidarscout::viewer::app
