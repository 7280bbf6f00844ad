// The ImGui panels of the viewer: the side window's sections and the point readout.
#include "viewer/app/panels.hpp"

#include <imgui.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cstdint>
#include <filesystem>
#include <vector>

#include "core/point_filter.hpp"
#include "core/text.hpp"
#include "las/classification.hpp"
#include "render/backend.hpp"
#include "render/colour_modes.hpp"
#include "viewer/patch_heightmap.hpp"

namespace lidarscout::viewer::app {
namespace {

constexpr float kSideWidth = 320;  // the side window's width in pixels
// The readout and progress windows: fitted to their text, in a fixed place.
constexpr auto kSmallWindow =
    ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoSavedSettings;

bool contains_ci(const std::string& text, const std::string& needle) {
    const auto it = std::search(text.begin(), text.end(), needle.begin(), needle.end(),
                                [](char a, char b) { return std::tolower(a) == std::tolower(b); });
    return it != text.end();
}

void progress_line(const char* label, StageProgress p) {
    const float f = p.total ? static_cast<float>(static_cast<double>(p.done) / p.total) : 1.0f;
    char text[96];
    std::snprintf(text, sizeof text, "%llu / %llu", (unsigned long long)p.done, (unsigned long long)p.total);
    ImGui::ProgressBar(f, ImVec2(-110, 0), text);
    ImGui::SameLine();
    ImGui::TextUnformatted(label);
}

// A text field editing `text` (up to 255 bytes); true when it changed.
bool input_text(const char* label, std::string& text) {
    char buffer[256];
    std::snprintf(buffer, sizeof buffer, "%s", text.c_str());
    if (!ImGui::InputText(label, buffer, sizeof buffer)) return false;
    text = buffer;
    return true;
}

// Puts the next item, `width` pixels wide, on the line of the last one when it fits before the window's
// right edge, else on a line of its own: rows of buttons and checkboxes flow in the narrow side window
// instead of running out of it.
void same_line_if_fits(float width) {
    const float right = ImGui::GetItemRectMax().x + ImGui::GetStyle().ItemSpacing.x + width;
    if (right <= ImGui::GetWindowPos().x + ImGui::GetWindowContentRegionMax().x) ImGui::SameLine();
}

// A checkbox's or radio button's width: its box and its label.
float checkbox_width(const char* label) {
    return ImGui::GetFrameHeight() + ImGui::GetStyle().ItemInnerSpacing.x + ImGui::CalcTextSize(label).x;
}

float button_width(const char* label) {
    return ImGui::CalcTextSize(label).x + 2 * ImGui::GetStyle().FramePadding.x;
}

void tiles_section(const dataset::Dataset& ds, PanelState& state, PanelActions& actions) {
    if (!ImGui::CollapsingHeader("Tiles")) return;
    input_text("filter", state.filter);
    const auto name = [&](std::uint32_t i) {
        return std::filesystem::path(ds.path(i)).filename().string();
    };
    if (state.shown_dataset != &ds || state.shown_tiles != ds.tiles.size() || state.shown_filter != state.filter) {
        state.shown.clear();
        for (std::uint32_t i = 0; i < ds.tiles.size(); ++i) {
            if (state.filter.empty() || contains_ci(name(i), state.filter)) state.shown.push_back(i);
        }
        state.shown_dataset = &ds, state.shown_tiles = ds.tiles.size(), state.shown_filter = state.filter;
    }
    const auto& shown = state.shown;
    ImGui::Text("%zu of %zu tiles (double-click: fly there)", shown.size(), ds.tiles.size());
    ImGui::BeginChild("list", ImVec2(0, 150), true);
    ImGuiListClipper clipper;
    clipper.Begin(static_cast<int>(shown.size()));
    while (clipper.Step()) {
        for (int k = clipper.DisplayStart; k < clipper.DisplayEnd; ++k) {
            const std::uint32_t i = shown[k];
            ImGui::PushID(static_cast<int>(i));
            if (ImGui::Selectable(name(i).c_str(), state.selected == i, ImGuiSelectableFlags_AllowDoubleClick)) {
                state.selected = i;
                if (ImGui::IsMouseDoubleClicked(0)) actions.fly_to = i;
            }
            ImGui::PopID();
        }
    }
    ImGui::EndChild();
}

void stats_section(const dataset::Dataset& ds, const SchedulerStats& s, double frame_ms) {
    if (!ImGui::CollapsingHeader("Stats and progress", ImGuiTreeNodeFlags_DefaultOpen)) return;
    ImGui::TextWrapped("tiles %zu (%zu skipped), %s points", s.tiles, ds.skipped.size(),
                       count_text(static_cast<double>(ds.point_count)).c_str());
    ImGui::TextWrapped("chunk points %llu", (unsigned long long)s.chunk_points_loaded);
    ImGui::TextWrapped("heightmaps: %zu linear, %zu network", s.heightmaps_linear, s.heightmaps_cnn);
    ImGui::TextWrapped("full-res: %zu tiles, %s points, %zu released", s.full_res_tiles,
                       count_text(static_cast<double>(s.full_res_points)).c_str(), s.full_res_released);
    ImGui::TextWrapped("coarse kept: %zu tiles; LOD %s points", s.coarse_tiles,
                       count_text(static_cast<double>(s.lod_points)).c_str());
    ImGui::TextWrapped("memory %.0f / %.0f MiB (peak %.0f)", s.bytes_used / 1048576.0,
                       s.memory_budget / 1048576.0, s.peak_bytes_used / 1048576.0);
    ImGui::TextWrapped("frame %.1f ms (%.1f fps)", frame_ms, frame_ms > 0 ? 1000.0 / frame_ms : 0.0);
    ImGui::Separator();
    progress_line("tiles", s.tiles_loaded);
    progress_line("chunk points", s.chunk_points);
    progress_line("linear", s.linear);
    if (s.cnn.total) progress_line("network", s.cnn);
    if (s.surface_pending) ImGui::Text("surface: %zu patches to lay over again", s.surface_pending);
    progress_line("full-res", s.full_res);
    for (const auto& note : s.notes) ImGui::TextWrapped("%s", note.c_str());
}

// One line per file that could not be opened, per failure while streaming (file, offset, cause), and
// per warning about the dataset (tiles named more than once, CRSs mixed, a header that corrects its item).
void errors_section(const dataset::Dataset& ds, const SchedulerStats& s) {
    const auto per_file = first_error_per_file(s.errors);
    const std::size_t count = ds.skipped.size() + per_file.size();
    const std::size_t warnings = ds.warnings.size() + ds.corrections_count();
    if (count + warnings == 0) return;
    const std::string title =
        "Errors: " + std::to_string(count) + " files, " + std::to_string(warnings) + " warnings###errors";
    if (!ImGui::CollapsingHeader(title.c_str())) return;
    ImGui::BeginChild("errors", ImVec2(0, std::min(200.0f, 20.0f + 34.0f * (count + warnings))), true,
                      ImGuiWindowFlags_HorizontalScrollbar);
    for (const auto& w : ds.warnings) ImGui::TextWrapped("%s: %s", level_name(w.level), w.message.c_str());
    for (const auto& w : ds.corrections()) ImGui::TextWrapped("%s: %s", level_name(w.level), w.message.c_str());
    for (const auto& f : ds.skipped) ImGui::TextWrapped("skipped: %s", f.error.c_str());
    for (const auto& e : per_file) {
        if (e.count == 1) ImGui::TextWrapped("%s", e.first.message().c_str());
        else ImGui::TextWrapped("%s (and %zu more in this file)", e.first.message().c_str(), e.count - 1);
    }
    ImGui::EndChild();
}

void settings_section(ViewSettings& v, PanelActions& actions) {
    if (!ImGui::CollapsingHeader("Settings")) return;
    if (ImGui::InputInt("memory MiB", &v.budget_mb, 256, 1024, ImGuiInputTextFlags_EnterReturnsTrue)) {
        v.budget_mb = std::max(64, v.budget_mb);
        actions.budget_changed = true;
    }
    ImGui::SliderInt("point size", &v.style.point_size, 1, 8);
    ImGui::Checkbox("near points as wide as their spacing", &v.style.adaptive_point_size);
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
}

// Class checkboxes: the LAS 1.4 classes 0-22 and any other class held, with the points held.
void class_checkboxes(PointFilter& f, const std::array<std::uint64_t, 256>& held) {
    if (ImGui::SmallButton("all classes")) f.classes.set();
    ImGui::SameLine();
    if (ImGui::SmallButton("no class")) f.classes.reset();
    for (unsigned c = 0; c < 256; ++c) {
        if (c > 22 && held[c] == 0) continue;
        bool keep = f.classes.test(c);
        const std::string label = std::to_string(c) + " " + las::class_name(static_cast<std::uint8_t>(c)) +
                                  (held[c] ? " (" + std::to_string(held[c]) + ")" : "");
        if (ImGui::Checkbox(label.c_str(), &keep)) f.classes.set(c, keep);
    }
}

void return_checkboxes(PointFilter& f) {
    static constexpr std::pair<std::uint8_t, const char*> kKinds[] = {
        {returns::kFirst, "first"}, {returns::kLast, "last"}, {returns::kSingle, "single"},
        {returns::kIntermediate, "intermediate"}};
    ImGui::TextUnformatted("returns:");
    for (const auto& [bit, name] : kKinds) {
        same_line_if_fits(checkbox_width(name));
        bool on = (f.return_kinds & bit) != 0;
        if (ImGui::Checkbox(name, &on)) f.return_kinds = on ? (f.return_kinds | bit) : (f.return_kinds & ~bit);
    }
}

// Which points are drawn (and picked): presets, classes, return kinds, intensity.
void filters_section(ViewSettings& v, const PanelState& state) {
    PointFilter& f = v.style.filter;
    // Open from the start when the viewer was opened with a filter (view --classes ...).
    if (!ImGui::CollapsingHeader("Filters", f.keeps_everything() ? 0 : ImGuiTreeNodeFlags_DefaultOpen)) return;
    const auto presets = filter_presets();
    for (std::size_t k = 0; k < presets.size(); ++k) {
        const std::string name(presets[k].name);
        if (k > 0) same_line_if_fits(button_width(name.c_str()));
        if (ImGui::SmallButton(name.c_str())) f = presets[k].filter;
    }
    ImGui::TextWrapped("drawn: %s", f.describe().c_str());
    return_checkboxes(f);
    int range[2] = {f.intensity_min, f.intensity_max};
    if (ImGui::DragInt2("intensity", range, 16.0f, 0, 65535)) {
        f.intensity_min = static_cast<std::uint16_t>(std::clamp(std::min(range[0], range[1]), 0, 65535));
        f.intensity_max = static_cast<std::uint16_t>(std::clamp(std::max(range[0], range[1]), 0, 65535));
    }
    if (const Surface surface = surface_of(f); surface != Surface::All) {
        ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(0.85f, 0.35f, 0.85f, 1.0f));
        ImGui::TextWrapped("Heightmaps: %s (bare earth) where tiles were read; tinted violet: the overview of every "
                           "point, not filtered (tiles not read yet).", surface_name(surface));
        ImGui::PopStyleColor();
    }
    ImGui::TextWrapped("Points held for the view by class. Chunk points have no returns (a return filter lets "
                       "them through); heightmaps follow a ground or water filter only.");
    class_checkboxes(f, state.loaded_classes);
}

// Labels at picked points, measurements kept, the session saved.
void labels_section(PanelState& state, PanelActions& actions) {
    if (!ImGui::CollapsingHeader("Labels and session")) return;
    input_text("label", state.label);
    ImGui::BeginDisabled(!state.click.picked || state.label.empty());
    if (ImGui::Button("label the picked point")) {
        const PickedPoint& p = *state.click.picked;
        state.annotations.push_back({{p.x, p.y, p.z}, state.label});
        state.label.clear();
    }
    ImGui::EndDisabled();
    ImGui::BeginDisabled(!state.click.from || !state.click.to);
    if (ImGui::Button("keep the measurement")) {
        const PickedPoint &a = *state.click.from, &b = *state.click.to;
        state.measurements.push_back({{a.x, a.y, a.z}, {b.x, b.y, b.z}});
    }
    ImGui::EndDisabled();
    for (std::size_t k = 0; k < state.annotations.size(); ++k) {
        ImGui::PushID(static_cast<int>(k));
        if (ImGui::SmallButton("x")) {
            state.annotations.erase(state.annotations.begin() + static_cast<std::ptrdiff_t>(k));
            ImGui::PopID();
            break;
        }
        ImGui::SameLine();
        ImGui::TextUnformatted(state.annotations[k].text.c_str());
        ImGui::PopID();
    }
    if (!state.measurements.empty() && ImGui::SmallButton("forget the measurements kept")) state.measurements.clear();
    auto& kept = state.profile.kept;
    for (std::size_t k = 0; k < kept.size(); ++k) {  // the profiles kept: open one again, or forget it
        ImGui::PushID(static_cast<int>(1000000 + k));
        if (ImGui::SmallButton("x")) {
            kept.erase(kept.begin() + static_cast<std::ptrdiff_t>(k));
            ImGui::PopID();
            break;
        }
        ImGui::SameLine();
        if (ImGui::SmallButton("open")) actions.open_kept_profile = k;
        ImGui::SameLine();
        ImGui::TextWrapped("profile %.1f,%.1f - %.1f,%.1f (%.2f wide)", kept[k].line[0], kept[k].line[1],
                           kept[k].line[2], kept[k].line[3], kept[k].width);
        ImGui::PopID();
    }
    input_text("session file", state.session_path);
    if (ImGui::Button("save session")) actions.save_session = true;
}

// The click tool, the screenshot button and the help line: always shown.
void tool_bar(PanelState& state, PanelActions& actions) {
    int tool = static_cast<int>(state.click.tool);  // what a click does
    static constexpr std::pair<ClickTool, const char*> kTools[] = {
        {ClickTool::Inspect, "inspect"}, {ClickTool::Measure, "measure"}, {ClickTool::Area, "area"},
        {ClickTool::Profile, "profile"}};
    // a little closer than other items: the four stay on one line beside the side window's scrollbar
    ImGui::PushStyleVar(ImGuiStyleVar_ItemSpacing, ImVec2(6, ImGui::GetStyle().ItemSpacing.y));
    for (const auto& [value, name] : kTools) {
        if (value != ClickTool::Inspect) same_line_if_fits(checkbox_width(name));
        ImGui::RadioButton(name, &tool, static_cast<int>(value));
    }
    ImGui::PopStyleVar();
    state.click.use(static_cast<ClickTool>(tool));
    if (ImGui::Button("screenshot")) actions.screenshot = true;
    if (!state.status.empty()) ImGui::TextWrapped("%s", state.status.c_str());
    if (!state.exports.status.empty()) {
        ImGui::TextWrapped("%s", state.exports.status.c_str());
        if (state.exports.running && ImGui::SmallButton("cancel the export")) actions.cancel_export = true;
    }
    if (!state.cursor.empty()) ImGui::TextWrapped("cursor %s", state.cursor.c_str());
    if (ImGui::CollapsingHeader("Help")) {
        ImGui::TextWrapped("left drag: orbit, right drag: pan, wheel: zoom, WASD/QE: fly (shift: faster); "
                           "click: inspect a point, measure, an area's vertices or a profile's line; F12: "
                           "screenshot; drop a folder or files to open them");
    }
}

void point_lines(const dataset::Dataset& ds, const char* label, const PickedPoint& p) {
    const PointReadout r = point_readout(ds, p);
    ImGui::Text("%s x %.3f  y %.3f  z %.3f", label, r.x, r.y, r.z);
    ImGui::Text("   %s, z in %s%s%s", r.horizontal_unit.c_str(), r.vertical_unit.c_str(), r.crs.empty() ? "" : ", ",
                r.crs.c_str());
    if (p.lonlat) ImGui::Text("   lon %.7f, lat %.7f", (*p.lonlat)[0], (*p.lonlat)[1]);
    if (p.surface) {
        ImGui::Text("   heightmap surface (interpolated, not a measured point)");
    } else {
        ImGui::Text("   class %u (%s), intensity %u, rgb %u %u %u%s", p.classification,
                    las::class_name(p.classification).c_str(), p.intensity, p.r, p.g, p.b,
                    p.chunk_point ? ", chunk point" : "");
    }
    if (!r.file.empty()) ImGui::TextWrapped("   %s", std::filesystem::path(r.file).filename().c_str());
}

// The picked point or the measurement, in a small window at the bottom right.
// The area tool's readout: the vertices so far, the measurement or how to get it.
void area_lines(ClickState& click, ExportPanel& exports, PanelActions& actions) {
    ImGui::Text("%zu vertices", click.polygon.size());
    if (click.polygon.size() >= 3) {  // the points inside, every one of the tiles under it, as LAZ
        ImGui::SetNextItemWidth(160);
        input_text("##clip", exports.clip_path);
        ImGui::SameLine();
        ImGui::BeginDisabled(exports.running);
        if (ImGui::Button("export the points inside")) actions.export_clip = true;
        ImGui::EndDisabled();
    }
    if (click.area) {
        ImGui::TextWrapped("%s", click.area->c_str());
        ImGui::TextUnformatted("the next click starts a new polygon");
    } else if (click.polygon.size() >= 3) {
        if (ImGui::Button("measure area and volume")) actions.measure_area = true;
    } else {
        ImGui::TextUnformatted("click the polygon's vertices on the ground");
    }
}

// The profile tool's readout: the width of the next corridor, the ends clicked so far.
void profile_lines(const ClickState& click, ProfilePanel& profile) {
    ImGui::SetNextItemWidth(120);
    if (ImGui::InputDouble(("width (" + profile.unit + ")").c_str(), &profile.width, 0, 0, "%.2f")) {
        profile.width = std::max(profile.width, 0.01);
    }
    ImGui::TextUnformatted(!click.from ? "click the line's first end on the ground"
                           : !click.to ? "click its second end"
                                       : "the next click starts a new line");
}

void readout_window(const dataset::Dataset& ds, ClickState& click, PanelState& state, PanelActions& actions) {
    const bool any = click.picked || click.from || click.missed || !click.polygon.empty() ||
                     click.tool == ClickTool::Profile;
    if (!any) return;
    const ImVec2 display = ImGui::GetIO().DisplaySize;
    ImGui::SetNextWindowPos(ImVec2(display.x - 10, display.y - 10), ImGuiCond_Always, ImVec2(1, 1));
    ImGui::SetNextWindowBgAlpha(0.8f);
    const char* title = click.tool == ClickTool::Measure   ? "Measure"
                        : click.tool == ClickTool::Area    ? "Area"
                        : click.tool == ClickTool::Profile ? "Profile line"
                                                           : "Point";
    if (!ImGui::Begin(title, nullptr, kSmallWindow)) return ImGui::End();
    if (click.tool == ClickTool::Area) area_lines(click, state.exports, actions);
    if (click.tool == ClickTool::Profile) profile_lines(click, state.profile);
    if (click.picked) point_lines(ds, "", *click.picked);
    if (click.from) point_lines(ds, "A", *click.from);
    if (click.to) {
        point_lines(ds, "B", *click.to);
        ImGui::Separator();
        ImGui::TextWrapped("%s", measurement_summary(measure(*click.from, *click.to)).c_str());
    } else if (click.from && click.tool == ClickTool::Measure) {
        ImGui::TextUnformatted("click the second point");
    }
    if (click.missed) ImGui::TextUnformatted("nothing under the cursor (sky, or a hole in the data)");
    ImGui::End();
}

// The profile's window at the top right: the plot (distance left to right, height bottom to top),
// what it spans, the read's progress, colours, export, keep, close.
void profile_window(ProfilePanel& p, const ExportPanel& exports, PanelActions& actions) {
    if (!p.open) return;
    const ImVec2 display = ImGui::GetIO().DisplaySize;
    const float width = std::clamp(display.x - kSideWidth - 40, 240.0f, 760.0f);
    ImGui::SetNextWindowPos(ImVec2(display.x - 10, 10), ImGuiCond_FirstUseEver, ImVec2(1, 0));
    ImGui::SetNextWindowSize(ImVec2(width, 0), ImGuiCond_Always);  // 0: the height fits the plot and its lines
    ImGui::SetNextWindowBgAlpha(0.9f);
    bool open = true;
    if (ImGui::Begin("Profile", &open, ImGuiWindowFlags_NoSavedSettings)) {
        ImGui::TextWrapped("%s", p.title.c_str());
        if (p.texture && p.texture_width > 0) {
            const float w = ImGui::GetContentRegionAvail().x;
            ImGui::Image(reinterpret_cast<ImTextureID>(static_cast<std::intptr_t>(p.texture)),
                         ImVec2(w, w * p.texture_height / p.texture_width));
        }
        if (!p.axes.empty()) ImGui::TextWrapped("%s", p.axes.c_str());
        ImGui::TextWrapped("%s", p.status.c_str());
        if (ImGui::Checkbox("coloured by elevation (else by class)", &p.elevation)) actions.profile_colours = true;
        if (p.filter_changed) {
            ImGui::TextWrapped("read with another filter than the one drawn now");
            if (ImGui::SmallButton("read again with the filter drawn")) actions.reread_profile = true;
        }
        ImGui::SetNextItemWidth(std::max(100.0f, ImGui::GetContentRegionAvail().x - 230));
        input_text("##export", p.export_path);
        ImGui::SameLine();
        ImGui::BeginDisabled(exports.running);
        if (ImGui::Button("export .csv/.laz/.png")) actions.export_profile = true;
        ImGui::EndDisabled();
        if (ImGui::Button("keep (saved with the session)")) actions.keep_profile = true;
        ImGui::SameLine();
        if (ImGui::Button("close")) open = false;
    }
    ImGui::End();
    if (!open) actions.close_profile = true;
}

}  // namespace

PanelActions draw_panels(const dataset::Dataset& dataset, const SchedulerStats& stats, double frame_ms,
                         ViewSettings& settings, PanelState& state) {
    PanelActions actions;
    // One side window of collapsible sections, a quarter of a 1280-wide window at most.
    const ImVec2 display = ImGui::GetIO().DisplaySize;
    ImGui::SetNextWindowPos(ImVec2(10, 10), ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowSize(ImVec2(kSideWidth, 0), ImGuiCond_Always);  // 0: the height fits the open sections
    ImGui::SetNextWindowSizeConstraints(ImVec2(kSideWidth, 0), ImVec2(kSideWidth, std::max(100.0f, display.y - 20)));
    if (ImGui::Begin("lidarscout")) {
        tool_bar(state, actions);
        stats_section(dataset, stats, frame_ms);
        errors_section(dataset, stats);
        tiles_section(dataset, state, actions);
        filters_section(settings, state);
        labels_section(state, actions);
        settings_section(settings, actions);
    }
    ImGui::End();
    readout_window(dataset, state.click, state, actions);
    profile_window(state.profile, state.exports, actions);
    return actions;
}

void draw_labels(const std::vector<Annotation>& labels, const render::Camera& camera) {
    const ImVec2 display = ImGui::GetIO().DisplaySize;
    const float sx = display.x / static_cast<float>(std::max(1, camera.width));
    const float sy = display.y / static_cast<float>(std::max(1, camera.height));
    ImDrawList* draw = ImGui::GetForegroundDrawList();
    for (const auto& a : labels) {
        const auto at = camera.project(a.at[0], a.at[1], a.at[2]);
        if (!at) continue;
        const ImVec2 p(static_cast<float>(at->x) * sx, static_cast<float>(at->y) * sy);
        draw->AddCircleFilled(p, 4.0f, IM_COL32(255, 220, 60, 255));
        const ImVec2 text(p.x + 7, p.y - 8);
        draw->AddText(ImVec2(text.x + 1, text.y + 1), IM_COL32(0, 0, 0, 255), a.text.c_str());
        draw->AddText(text, IM_COL32(255, 240, 160, 255), a.text.c_str());
    }
}

void draw_opening_panel(const OpeningProgress& p) {
    const ImVec2 display = ImGui::GetIO().DisplaySize;
    ImGui::SetNextWindowPos(ImVec2(10, display.y - 10), ImGuiCond_Always, ImVec2(0, 1));
    ImGui::SetNextWindowBgAlpha(0.8f);
    if (ImGui::Begin("Opening", nullptr, kSmallWindow)) {
        if (p.total == 0) {
            ImGui::TextUnformatted("finding the tiles...");
        } else {
            ImGui::Text("%zu of %zu files read, %zu failed%s", p.read, p.total, p.done - p.read,
                        p.building ? "; starting the overview" : "");
            progress_line("files", {p.done, p.total});
        }
    }
    ImGui::End();
}

}  // namespace lidarscout::viewer::app
