// The viewer's Dear ImGui panels: one narrow side window of collapsible sections (stats and
// progress of each stage; tiles: filter, double-click flies there; filters: presets, classes with
// their counts, return kinds, intensity; settings: memory budget, point sizes, colour mode, EDL,
// layers; labels and the session: text labels at picked points, measurements kept, saving the
// session; the click tool; the errors, one line per unreadable file with
// its cause), a small readout window for the picked point, the measurement or the area (with its
// clip export), a profile window (the plot, its progress and exports); while a dataset opens, a
// progress window. They read the
// scheduler's stats and write the settings; actions come back as a PanelActions.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "dataset/dataset.hpp"
#include "viewer/picking.hpp"
#include "viewer/scheduler.hpp"
#include "viewer/scene.hpp"
#include "viewer/scene_snapshot.hpp"
#include "viewer/session_file.hpp"
#include "viewer/session_opening.hpp"

namespace lidarscout::viewer::app {

struct ViewSettings {
    SceneStyle style;
    SceneLayers layers;
    bool tile_boxes = false;
    int budget_mb = 0;          // memory budget shown and edited in MiB
    float render_scale = 1.0f;  // rendered pixels per window pixel (lower = faster)
};

// The profile shown (the loop fills it every frame) and what its window edits.
struct ProfilePanel {
    double width = 2;          // the corridor's width for the next line clicked, the CRS's units
    std::string unit = "m";    // the CRS's horizontal unit
    bool open = false;         // a profile is shown
    std::string title;         // its line and width
    std::string status;        // the read's progress, then its points (or why it failed)
    std::string axes;          // what the plot spans (the image has no text)
    unsigned texture = 0;      // the plot (GL texture) and its size in pixels
    int texture_width = 0, texture_height = 0;
    bool elevation = false;        // coloured by elevation, not by class
    bool filter_changed = false;   // read with another filter than the one drawn now
    std::string export_path = "profile.csv";
    std::vector<SavedProfile> kept;  // profiles kept (saved with the session)
};

// The background export (one at a time): its file names and the line it shows.
struct ExportPanel {
    std::string clip_path = "area.laz";
    std::string status;
    bool running = false;
};

struct PanelState {
    std::string filter;
    // The tiles the filter lets through, found again only when the filter or the dataset changes
    // (a country has 150,000 tiles: not every frame).
    std::vector<std::uint32_t> shown;
    std::string shown_filter;
    const dataset::Dataset* shown_dataset = nullptr;
    std::size_t shown_tiles = 0;
    std::optional<std::uint32_t> selected;
    std::string status;  // one line: the last screenshot, an error
    ClickState click;    // the click tool and what it picked
    std::string cursor;  // the ground under the cursor (viewer/cursor_readout.hpp)
    std::array<std::uint64_t, 256> loaded_classes{};  // full-resolution points held for the view, by class
    std::vector<Annotation> annotations;              // text labels at picked points
    std::vector<SavedMeasurement> measurements;       // measurements kept (drawn, saved with the session)
    std::string label;                                // the text of the next label
    std::string session_path = "view.lidarscout.json";  // where "save session" writes
    ProfilePanel profile;
    ExportPanel exports;
};

struct PanelActions {
    std::optional<std::uint32_t> fly_to;  // a tile double-clicked
    bool budget_changed = false;
    bool screenshot = false;
    bool save_session = false;
    bool measure_area = false;  // the area tool's polygon is to be measured
    bool close_profile = false, reread_profile = false, keep_profile = false, profile_colours = false;
    std::optional<std::size_t> open_kept_profile;  // of ProfilePanel::kept
    bool export_profile = false, export_clip = false, cancel_export = false;
};

// Draws the panels for this frame (between ImGui::NewFrame and ImGui::Render).
PanelActions draw_panels(const dataset::Dataset& dataset, const SchedulerStats& stats, double frame_ms,
                         ViewSettings& settings, PanelState& state);

// The labels over the window: each annotation's text at its point as `camera` (the rendered
// image's) sees it, scaled to the window.
void draw_labels(const std::vector<Annotation>& labels, const render::Camera& camera);

// A small window while a dataset opens: files read (failed) of the files found, with a bar.
void draw_opening_panel(const OpeningProgress& progress);

}  // namespace lidarscout::viewer::app
