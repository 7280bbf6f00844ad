// The interactive viewer (`lidarscout view`): a GLFW window showing the software rasterizer's
// image of a Scheduler's snapshot every frame, Dear ImGui panels, mouse and keyboard camera
// controls, picking, measuring, areas and profiles by clicks, exports of a profile or of an area's
// points, drag-and-drop of folders or files, F12 screenshots, and a scripted mode that clicks, writes
// the last frame (or the whole window), a profile or an area's points and quits after a time.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/point_filter.hpp"
#include "pipelines/profile.hpp"
#include "render/backend.hpp"
#include "viewer/overview_cache.hpp"
#include "viewer/session_file.hpp"

namespace lidarscout::viewer::app {

struct ViewerOptions {
    std::vector<std::string> paths;  // what to open (files, folders, tile lists)
    int width = 1280, height = 720;  // window size
    std::uint64_t memory_budget = 0; // of the whole process (0 = a quarter of the RAM)
    bool cnn = true;
    std::string model;               // empty = the default model lookup
    std::string crs;                 // the CRS tiles are reprojected to; empty = the majority's
    std::string screenshot;          // scripted: the last frame's PNG
    std::string window_screenshot;   // scripted: the whole window (panels included) as a PNG
    double quit_after = 0;           // scripted: seconds after the dataset is open (0 = until closed)
    std::vector<std::pair<double, double>> clicks;  // scripted: window pixels clicked at quit_after
    bool measure = false;            // scripted: the clicks measure instead of inspecting
    bool area = false;               // scripted: the clicks are a polygon, measured (area, volume) at the end
    std::string clip_out;            // scripted (with area): the polygon's points written to this .laz/.las
    std::optional<pipelines::Corridor> profile;  // a profile opened at start (the dataset CRS's units)
    std::string profile_out;         // scripted: that profile written here (.csv/.laz/.las/.png) once read
    PointFilter filter;              // the points drawn at first (the Filters section changes them)
    std::optional<SessionFile> session;  // opened with `view --session`: camera, filter, labels ... applied
    std::string session_path;        // that session's file (where the panel's "save session" writes)
    std::string save_session;        // scripted: the session written when the viewer ends
    unsigned threads = 0;            // rendering threads (0 = all cores)
    render::Backend backend = render::Backend::Cpu;  // the rasterizer (resolved: Cpu or Cuda)
    // Where the overview sidecar of a remote dataset is kept (viewer/overview_cache.hpp), for the first
    // opening (paths); unset: none kept or used.
    std::optional<OverviewCacheSettings> overview_cache;
};

// When the window showed what, in seconds from run_viewer's start (window creation included);
// unset: never happened.
struct ViewerTimings {
    std::optional<double> first_frame_s;     // the first frame presented (the dataset may still be opening)
    std::optional<double> footprints_s;      // the first frame with every tile's footprint (or the dataset open)
    std::optional<double> dataset_open_s;    // every tile's metadata read, the scheduler started
    std::optional<double> first_overview_s;  // the first frame presented with a heightmap
    std::optional<double> chunk_points_s;    // the first frame presented with every tile's chunk points in
    std::optional<double> nearest_full_s;    // the first with the tile nearest the camera (of most screen
                                             // coverage) whole at full resolution
    std::size_t frames_while_opening = 0;    // frames presented before the dataset was open
    std::size_t tiles = 0, skipped = 0;      // of the dataset shown at the end
    // Memory (viewer/process_budget.hpp), in bytes: the process's peak resident size (VmHWM), the
    // budget it was given, the scheduler's share at the end and its ledger's peak, what the program
    // held outside the ledger at most; the line saying the budget is below what the viewer needs, and the
    // one saying the overview leaves full resolution no room (at the end).
    std::uint64_t peak_resident_bytes = 0, budget_bytes = 0, data_budget_bytes = 0, ledger_peak_bytes = 0;
    std::uint64_t outside_bytes = 0;
    std::string budget_note, overview_note;
};

// Opens the window at once and the dataset in the background (the window shows the tiles'
// footprints and a progress line meanwhile), and runs until the window is closed (or
// quit_after, the scripted outputs written); `timings`, when given, gets the figures above. Returns
// 1 when a scripted output (profile_out, clip_out) failed, else 0. Throws lidarscout::Error when no
// window can be opened (no display) or nothing readable is in the paths.
int run_viewer(const ViewerOptions& options, ViewerTimings* timings = nullptr);

}  // namespace lidarscout::viewer::app
