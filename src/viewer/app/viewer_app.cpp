// The viewer's window loop: GLFW + OpenGL (epoxy) for the window and the image, ImGui for the
// panels, the Scheduler for the data, render_snapshot for the picture.
#include "viewer/app/viewer_app.hpp"

#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <algorithm>
#include <iterator>
#include <filesystem>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <memory>
#include <thread>
#include <utility>

#include "core/error.hpp"
#include "core/process_memory.hpp"
#include "core/text.hpp"
#include "core/thread_pool.hpp"
#include "core/throttle.hpp"
#include "dataset/dataset.hpp"
#include "dataset/json_file.hpp"
#include "dataset/stac_catalog.hpp"
#include "dataset/virtual_replica.hpp"
#include "io/file.hpp"
#include "render/resolve.hpp"
#include "render/png_writer.hpp"
#include "viewer/app/camera_controller.hpp"
#include "viewer/app/gl_presenter.hpp"
#include "viewer/app/overlay.hpp"
#include "viewer/app/panels.hpp"
#include "core/polygon.hpp"
#include "viewer/area_tool.hpp"
#include "viewer/background_reads.hpp"
#include "viewer/cursor_readout.hpp"
#include "viewer/frame_change.hpp"
#include "viewer/frame_refiner.hpp"
#include "viewer/picking.hpp"
#include "viewer/process_budget.hpp"
#include "viewer/profile_tool.hpp"
#include "viewer/surface_pick.hpp"
#include "viewer/scheduler.hpp"
#include "viewer/session_opening.hpp"

namespace lidarscout::viewer::app {
namespace {

using Clock = std::chrono::steady_clock;

std::string glfw_error;  // the last GLFW error message (GLFW reports errors through a callback)

// Input gathered by GLFW callbacks between frames.
struct InputEvents {
    double wheel = 0;
    std::vector<std::string> dropped;
};

// Starts opening `paths` in the background (viewer/session_opening.hpp), with the share of the
// process's budget that `plan` leaves to data (and the network when it fits).
// `first`: nothing is shown yet (else a preview of a large catalog would only delay its opening).
std::unique_ptr<SessionOpening> start_opening(const std::vector<std::string>& paths, const ViewerOptions& o,
                                              bool first, const ProcessBudgetPlan& plan) {
    SessionOptions so;
    so.crs = o.crs;
    if (!first) so.preview_above = 0;
    so.scheduler.memory_budget = plan.data;
    so.scheduler.cnn = o.cnn && plan.network;
    so.scheduler.network_asks_room = true;  // budget_step answers, once the dataset's own share is seen
    so.scheduler.model_path = o.model;
    so.scheduler.content_snapshot_interval_s = 0.1;  // as often as the frame refiner draws new data
    if (first && o.overview_cache) so.overview_cache = std::make_shared<OverviewCache>(paths, *o.overview_cache);
    return std::make_unique<SessionOpening>(paths, std::move(so));
}

void print_warnings(const Diagnostics& warnings) {
    for (const auto& w : warnings) {
        std::fprintf(stderr, "lidarscout: %s: %s\n", level_name(w.level), display_text(w.message).c_str());
    }
}

// Puts the finished opening's session in place of the one shown, its dataset's warnings on stderr too
// (the errors panel lists them). An error ends the viewer when nothing is shown yet (the first
// dataset), else it is the status line. True when replaced.
bool take_opening(std::unique_ptr<SessionOpening>& opening, Session& session, PanelState& panels) {
    const auto finished = std::move(opening);
    try {
        Session next = finished->take();
        session.scheduler.reset();  // it reads the dataset it replaces
        session.overview_cache.reset();  // (its write, too)
        session = std::move(next);
        panels = {};
        print_warnings(session.dataset->warnings);
        return true;
    } catch (const Error& e) {
        if (!session.open()) throw;
        panels.status = e.what();
        return false;
    }
}

struct GlfwWindow {
    GLFWwindow* window = nullptr;
    GlfwWindow(int width, int height, const char* title) {
        glfwSetErrorCallback([](int, const char* text) { glfw_error = text ? text : ""; });
        if (!glfwInit()) {
            throw Error("view: cannot open a window (no display? set DISPLAY or use xvfb-run): " + glfw_error);
        }
        glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
        glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
        glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
        window = glfwCreateWindow(width, height, title, nullptr, nullptr);
        if (!window) {
            glfwTerminate();
            throw Error("view: cannot create an OpenGL 3.3 window: " + glfw_error);
        }
        glfwMakeContextCurrent(window);
        glfwSwapInterval(1);
    }
    ~GlfwWindow() {
        glfwDestroyWindow(window);
        glfwTerminate();
    }
};

struct GuiContext {
    explicit GuiContext(GLFWwindow* window) {
        IMGUI_CHECKVERSION();
        ImGui::CreateContext();
        ImGui::GetIO().IniFilename = nullptr;
        ImGui::StyleColorsDark();
        ImGui_ImplGlfw_InitForOpenGL(window, true);  // chains to the callbacks installed before
        ImGui_ImplOpenGL3_Init("#version 330");
    }
    ~GuiContext() {
        ImGui_ImplOpenGL3_Shutdown();
        ImGui_ImplGlfw_Shutdown();
        ImGui::DestroyContext();
    }
};

void install_callbacks(GLFWwindow* window, InputEvents& events) {
    glfwSetWindowUserPointer(window, &events);
    glfwSetScrollCallback(window, [](GLFWwindow* w, double, double dy) {
        static_cast<InputEvents*>(glfwGetWindowUserPointer(w))->wheel += dy;
    });
    glfwSetDropCallback(window, [](GLFWwindow* w, int count, const char** paths) {
        auto* e = static_cast<InputEvents*>(glfwGetWindowUserPointer(w));
        e->dropped.assign(paths, paths + count);
    });
}

// Mouse drags, wheel and WASD turned into camera moves (unless the GUI wants the input).
class MouseKeyboard {
public:
    void apply(GLFWwindow* window, InputEvents& events, CameraController& controller, double seconds, int height) {
        double x = 0, y = 0;
        glfwGetCursorPos(window, &x, &y);
        const ImGuiIO& io = ImGui::GetIO();
        const bool left = glfwGetMouseButton(window, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS;
        const bool right = glfwGetMouseButton(window, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS;
        if ((left || right) && !dragging_) dragging_ = !io.WantCaptureMouse;
        track_click(left, x, y);
        if (!left && !right) dragging_ = false;
        if (dragging_ && has_last_) {
            if (left) controller.orbit(x - last_x_, y - last_y_);
            else controller.pan(x - last_x_, y - last_y_, height);
        }
        last_x_ = x, last_y_ = y, has_last_ = true;
        if (!io.WantCaptureMouse && events.wheel != 0) controller.zoom(events.wheel);
        events.wheel = 0;
        if (io.WantCaptureKeyboard) return;
        const auto down = [&](int key) { return glfwGetKey(window, key) == GLFW_PRESS; };
        FlyKeys keys{down(GLFW_KEY_W), down(GLFW_KEY_S), down(GLFW_KEY_A), down(GLFW_KEY_D),
                     down(GLFW_KEY_E), down(GLFW_KEY_Q), down(GLFW_KEY_LEFT_SHIFT) || down(GLFW_KEY_RIGHT_SHIFT)};
        controller.fly(keys, seconds);
    }
    // True once per press of `key`.
    bool pressed(GLFWwindow* window, int key) {
        const bool now = glfwGetKey(window, key) == GLFW_PRESS;
        const bool edge = now && !key_down_;
        key_down_ = now;
        return edge && !ImGui::GetIO().WantCaptureKeyboard;
    }

    // The window position of a left click (press and release in nearly the same place, on the
    // picture rather than a panel) since the last call, once.
    std::optional<std::pair<double, double>> take_click() { return std::exchange(click_, std::nullopt); }

private:
    void track_click(bool left, double x, double y) {
        if (left && !left_down_) press_ = dragging_ ? std::optional(std::pair(x, y)) : std::nullopt;
        if (!left && left_down_ && press_ && std::hypot(x - press_->first, y - press_->second) < 4) click_ = press_;
        left_down_ = left;
    }

    bool dragging_ = false, has_last_ = false, key_down_ = false, left_down_ = false;
    double last_x_ = 0, last_y_ = 0;
    std::optional<std::pair<double, double>> press_, click_;
};

// Picks the point under a click (window coordinates) in the frame drawn with `camera`.
void pick_at_click(GLFWwindow* window, std::pair<double, double> click, const Session& s,
                   const render::Camera& camera, const PointFilter& filter, PanelState& panels) {
    int win_width = 1, win_height = 1;
    glfwGetWindowSize(window, &win_width, &win_height);
    const double sx = static_cast<double>(camera.width) / std::max(1, win_width);
    const double sy = static_cast<double>(camera.height) / std::max(1, win_height);
    PickOptions options;
    options.radius_px = std::max(2.0, 4 * sx);
    options.filter = filter;  // what is drawn is what can be picked
    auto point = pick(*s.scheduler->snapshot(), camera, click.first * sx, click.second * sy, options);
    if (point && s.cursor) point->lonlat = s.cursor->lonlat(point->x, point->y);
    panels.click.clicked(point);
}

// What the window is about to show, panels included: its back buffer before the swap (the
// front buffer is not kept by every driver).
render::RgbaImage window_pixels(GLFWwindow* window) {
    int w = 0, h = 0;
    glfwGetFramebufferSize(window, &w, &h);
    render::RgbaImage image;
    image.width = std::max(w, 1), image.height = std::max(h, 1);
    std::vector<std::uint32_t> rows(static_cast<std::size_t>(image.width) * image.height);
    glReadBuffer(GL_BACK);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glReadPixels(0, 0, image.width, image.height, GL_RGBA, GL_UNSIGNED_BYTE, rows.data());
    image.pixels.resize(rows.size());
    for (int y = 0; y < image.height; ++y) {  // GL's row 0 is the bottom; the window is opaque
        const auto* row = rows.data() + static_cast<std::size_t>(image.height - 1 - y) * image.width;
        for (int x = 0; x < image.width; ++x) {
            image.pixels[static_cast<std::size_t>(y) * image.width + x] = row[x] | 0xff000000u;
        }
    }
    return image;
}

// Scripted clicks report on stdout: the point (or that there was none) and the measurement.
void print_click(std::pair<double, double> at, const dataset::Dataset& ds, const ClickState& click) {
    std::optional<PickedPoint> vertex;
    if (click.tool == ClickTool::Area && !click.polygon.empty()) vertex = click.polygon.back();
    const bool two = click.tool == ClickTool::Measure || click.tool == ClickTool::Profile;
    const auto& point = two                             ? (click.to ? click.to : click.from)
                        : click.tool == ClickTool::Area  ? vertex
                                                         : click.picked;
    if (click.missed || !point) std::printf("click %.0f,%.0f: no point\n", at.first, at.second);
    else std::printf("click %.0f,%.0f: %s\n", at.first, at.second, point_summary(ds, *point).c_str());
    if (!click.missed && click.tool == ClickTool::Measure && click.from && click.to) {
        std::printf("measure: %s\n", measurement_summary(measure(*click.from, *click.to)).c_str());
    }
    std::fflush(stdout);
}

std::string screenshot_name() {
    char text[64];
    const std::time_t now = std::time(nullptr);
    std::strftime(text, sizeof text, "lidarscout-%Y%m%d-%H%M%S.png", std::localtime(&now));
    return text;
}

// `budget`: the process's, in bytes.
ViewSettings initial_settings(const dataset::Dataset& ds, std::uint64_t budget, const ViewerOptions& o) {
    ViewSettings v;
    v.style.backend = o.backend;
    v.style.filter = o.filter;
    v.style.colour = colour_settings(render::ColourMode::Rgb, ds.bounds_m.min_z, ds.bounds_m.max_z);
    v.budget_mb = static_cast<int>(std::min<std::uint64_t>(budget >> 20, 1u << 30));
    return v;
}

// A fingerprint of what ImGui draws this frame (its vertices, indices and commands, the display's size), continued
// from `seed`.
std::uint64_t fingerprint(const ImDrawData& d, std::uint64_t seed) {
    std::uint64_t h = viewer::fingerprint(&seed, sizeof seed);
    const float display[4] = {d.DisplaySize.x, d.DisplaySize.y, d.FramebufferScale.x, d.FramebufferScale.y};
    h = viewer::fingerprint(display, sizeof display, h);
    for (int i = 0; i < d.CmdListsCount; ++i) {
        const ImDrawList& list = *d.CmdLists[i];
        h = viewer::fingerprint(list.VtxBuffer.Data, list.VtxBuffer.size_in_bytes(), h);
        h = viewer::fingerprint(list.IdxBuffer.Data, list.IdxBuffer.size_in_bytes(), h);
        for (const ImDrawCmd& c : list.CmdBuffer) {
            const float clip[4] = {c.ClipRect.x, c.ClipRect.y, c.ClipRect.z, c.ClipRect.w};
            const std::uint64_t ids[4] = {reinterpret_cast<std::uint64_t>(c.TextureId), c.VtxOffset, c.IdxOffset,
                                          c.ElemCount};
            h = viewer::fingerprint(ids, sizeof ids, viewer::fingerprint(clip, sizeof clip, h));
        }
    }
    return h;
}

// One frame of text on the window, not counted as a frame: what OpenGL maps when it first draws is then in
// the program's share (a software OpenGL such as Mesa's llvmpipe under Xvfb maps its shader compiler, some
// 60 MB of LLVM, at its first draw; measured before it, that would later crowd the data out of the budget).
void draw_first_frame(GLFWwindow* window) {
    glClearColor(0, 0, 0, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    ImGui_ImplOpenGL3_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::NewFrame();
    ImGui::Begin("lidarscout");
    ImGui::TextUnformatted("opening...");
    ImGui::End();
    ImGui::Render();
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    glfwSwapBuffers(window);
}

// The budget the user gave (or the default) for the whole process; what it holds now, its window
// up and drawn once, no dataset read, is the program's share at start.
ProcessBudget process_budget(const ViewerOptions& o, GLFWwindow* window) {
    draw_first_frame(window);
    return ProcessBudget(o.memory_budget ? o.memory_budget : default_memory_budget(), resident_bytes(), o.cnn);
}

// The frame's picture into `frame`: the snapshot drawn at the render scale, then the tile outlines;
// `drawn` gets the snapshot drawn (the panels read it too: no second snapshot per frame). The picture is copied
// into `frame`'s pixels, not into new ones (a fresh 4 MB image a frame was 8% of the CPU while a country loaded,
// most of it in page faults).
void draw_frame(const Session& s, const CameraController& controller, const ViewSettings& v,
                const PanelState& panels, int fb_width, int fb_height, ThreadPool& pool, FrameRefiner& refiner,
                render::Camera& camera, std::shared_ptr<const SceneSnapshot>& drawn, RenderedScene& frame) {
    const int w = std::max(1, static_cast<int>(std::lround(fb_width * v.render_scale)));
    const int h = std::max(1, static_cast<int>(std::lround(fb_height * v.render_scale)));
    camera = controller.camera(w, h);
    s.scheduler->set_camera(camera);
    s.scheduler->set_surface(surface_of(v.style.filter));  // a ground filter shows bare earth (cheap when unchanged)
    SceneStyle style = v.style;
    style.colour = colour_settings(v.style.colour.mode, s.dataset->bounds_m.min_z, s.dataset->bounds_m.max_z);
    const bool loading = s.scheduler->points_loading();  // before the snapshot: when false, it holds all
    drawn = s.scheduler->snapshot();
    frame = refiner.draw(*drawn, camera, style, pool, v.layers, loading);
    if (v.tile_boxes) {
        draw_tile_boxes(frame.image, camera, *s.dataset, *s.places, render::pack_rgba(255, 200, 40), panels.selected);
    }
    draw_click_overlay(frame.image, camera, panels.click);
    for (const auto& m : panels.measurements) {
        draw_segment(frame.image, camera, m.from[0], m.from[1], m.from[2], m.to[0], m.to[1], m.to[2],
                     render::pack_rgba(255, 220, 60));
    }
}

// The picture while the first dataset opens: the footprints of the tiles read so far. `kept` is the last
// one: while the camera stays, only the footprints added since are drawn on it (a country's 152,100 each
// frame held a core while its dataset opened).
struct FootprintPicture {
    RenderedScene frame;
    render::Camera camera;
    std::size_t drawn = 0;  // footprints drawn on frame
};
const RenderedScene& opening_frame(std::span<const dataset::Bounds> footprints, const CameraController& controller,
                                   int width, int height, render::Camera& camera, FootprintPicture& kept) {
    camera = controller.camera(width, height);
    if (!(camera == kept.camera) || footprints.size() < kept.drawn || kept.frame.image.pixels.empty()) {
        kept.camera = camera;
        kept.drawn = 0;
        kept.frame.image.width = width, kept.frame.image.height = height;
        kept.frame.image.pixels.assign(static_cast<std::size_t>(width) * height, render::ResolveSettings{}.background);
    }
    draw_footprints(kept.frame.image, camera, footprints.subspan(kept.drawn), render::pack_rgba(255, 200, 40));
    kept.drawn = footprints.size();
    return kept.frame;
}

// The readout for the mouse position (window coordinates scaled to the rendered image).
std::string cursor_text(GLFWwindow* window, const CursorReadout& readout, const render::Camera& camera,
                        double ground_z) {
    int w = 0, h = 0;
    glfwGetWindowSize(window, &w, &h);
    double mx = 0, my = 0;
    glfwGetCursorPos(window, &mx, &my);
    if (w <= 0 || h <= 0 || mx < 0 || my < 0 || mx >= w || my >= h) return "";
    return readout.text(camera, mx * camera.width / w, my * camera.height / h, ground_z);
}

// Waits for input or until a 60th of a second after `frame_start` (the swap does not wait for
// the display everywhere, e.g. under Xvfb).
void wait_for_next_frame(Clock::time_point frame_start) {
    const double left = 1.0 / 60 - std::chrono::duration<double>(Clock::now() - frame_start).count();
    if (left > 0) glfwWaitEventsTimeout(left);
}

// Notes the times of the first frame presented, of the first with every tile's footprint (or the
// dataset open), of the first with a heightmap, of the first with every tile's chunk points in, and of the first
// with the tile nearest the camera at full resolution
// (`stats`: the scheduler's, taken for this frame's panels).
void count_frame(ViewerTimings& t, const Session& session, const SchedulerStats& stats, bool every_footprint,
                 bool with_heightmaps, double seconds) {
    if (!t.first_frame_s) t.first_frame_s = seconds;
    if (!t.footprints_s && (every_footprint || session.open())) t.footprints_s = seconds;
    if (!t.first_overview_s && with_heightmaps) t.first_overview_s = seconds;  // a large catalog's preview too
    if (!session.open()) {
        ++t.frames_while_opening;
        return;
    }
    if (!t.chunk_points_s && stats.tiles_loaded.done == stats.tiles_loaded.total) t.chunk_points_s = seconds;
    if (!t.nearest_full_s && stats.full_res_nearest) t.nearest_full_s = seconds;
}

// The window loop's state and its steps, one method each: opening datasets, input, the frame,
// the panels, their actions, the scripted end. run_viewer calls them in that order every frame.
class ViewerLoop {
public:
    // How long after the loop's start the first frame may wait for a catalog's footprints, so that it shows them (a
    // country's 152,100 were in the first frame, at 0.79-0.89 s, in four of five runs, the fifth's came at 0.99 s
    // before them; waiting 0.7 s, it had come before them in every run); the frame itself takes 0.05-0.15 s more.
    static constexpr std::chrono::milliseconds kFirstFrameWait{850};

    explicit ViewerLoop(const ViewerOptions& o)
        : o_(o), start_(Clock::now()), win_(o.width, o.height, "lidarscout"), gui_(win_.window),
          pool_(o.threads ? o.threads : std::max(1u, std::thread::hardware_concurrency())),
          budget_(process_budget(o, win_.window)), opening_(start_opening(o.paths, o, true, budget_.plan())),
          previous_(start_),
          scripted_clicks_done_(o.clicks.empty() && !o.measure) {
        install_callbacks(win_.window, events_);
        report_budget_note(budget_.plan());
        if (!o.session_path.empty()) panels_.session_path = o.session_path;  // "save session" writes it back
        const auto catalog = [](const std::string& p) {
            return dataset::is_stac_catalog(p) && !dataset::is_virtual_replica(p);  // both may end in .json
        };
        if (std::any_of(o.paths.begin(), o.paths.end(), catalog)) {
            // A catalog's footprints in the first frame, where they come in time for it to come within a second
            // (kFirstFrameWait from the loop's start: a country's 152,100 items, parsed in about 0.8 s, may not).
            const auto left = start_ + kFirstFrameWait - Clock::now();
            opening_->wait_for_sources(std::chrono::duration_cast<std::chrono::milliseconds>(left));
        }
    }

    // One frame; false when the viewer is to quit.
    bool frame() {
        if (glfwWindowShouldClose(win_.window)) return false;
        glfwPollEvents();
        const auto now = Clock::now();
        const double dt = std::chrono::duration<double>(now - previous_).count();
        previous_ = now;
        glfwGetFramebufferSize(win_.window, &fb_width_, &fb_height_);
        fb_width_ = std::max(1, fb_width_), fb_height_ = std::max(1, fb_height_);
        open_step();
        input_step(dt);
        draw_step(now);
        const PanelActions actions = present_step();
        wait_for_next_frame(now);  // no more than a display shows: leave the cores to the reads and heightmaps
        action_step(actions);
        budget_step();
        return !script_step();
    }

    // What the run leaves: the timings, the screenshots asked for.
    int finish(ViewerTimings* timings) {
        opening_.reset();  // a window closed while opening: cancel the reads not started
        if (session_.open()) {
            times_.tiles = session_.dataset->tiles.size();
            times_.skipped = session_.dataset->skipped.size();
        }
        memory_figures();
        if (timings) *timings = times_;
        if (!o_.save_session.empty() && session_.open()) write_session(o_.save_session, current_session());
        if (!o_.screenshot.empty()) render::write_png(o_.screenshot, last_.image);
        if (!o_.window_screenshot.empty()) render::write_png(o_.window_screenshot, window_shot_);
        return script_status_;
    }

private:
    // The camera, filter, colour, measurements and labels of a saved session (its paths were opened).
    void apply_session(const SessionFile& s) {
        if (s.camera) {
            controller_.target_x = s.camera->target[0], controller_.target_y = s.camera->target[1];
            controller_.target_z = s.camera->target[2], controller_.distance = s.camera->distance;
            controller_.yaw_deg = s.camera->yaw_deg, controller_.pitch_deg = s.camera->pitch_deg;
            controller_.fov_deg = s.camera->fov_deg;
        }
        settings_.style.filter = s.filter;
        if (!s.colour.empty()) settings_.style.colour.mode = render::parse_colour_mode(s.colour);
        panels_.measurements = s.measurements;
        panels_.annotations = s.annotations;
        panels_.profile.kept = s.profiles;
    }

    // What is shown now, as a session (with the fields of the session opened that this version does not know).
    SessionFile current_session() const {
        SessionFile s = o_.session.value_or(SessionFile{});
        s.version = kSessionVersion;
        s.paths.clear();
        for (const auto& p : paths_) {  // local paths absolute: the session may be opened from elsewhere
            s.paths.push_back(p.find("://") == std::string::npos ? std::filesystem::absolute(p).string() : p);
        }
        s.crs = o_.crs;
        s.camera = CameraPose{{controller_.target_x, controller_.target_y, controller_.target_z}, controller_.distance,
                              controller_.yaw_deg, controller_.pitch_deg, controller_.fov_deg};
        s.filter = settings_.style.filter;
        s.colour = std::string(render::colour_mode_name(settings_.style.colour.mode));
        s.measurements = panels_.measurements;
        s.annotations = panels_.annotations;
        s.profiles = panels_.profile.kept;
        if (profile_) {  // the profile shown, unless it is kept already
            const auto& c = profile_->corridor();
            const SavedProfile shown{{c.x0, c.y0, c.x1, c.y1}, c.width};
            if (std::find(s.profiles.begin(), s.profiles.end(), shown) == s.profiles.end()) s.profiles.push_back(shown);
        }
        return s;
    }

    // The area tool's polygon measured on a thread of its own (a measurement running is cancelled): its
    // points read again as clip reads them (viewer/area_tool.hpp), the filter applied.
    void measure_area_now() {
        area_job_.reset();
        panels_.click.area = "area: measuring";
        area_job_ = std::make_unique<ExportTask>(
            "", [&ds = *session_.dataset, polygon = panels_.click.polygon, filter = settings_.style.filter,
                 threads = job_threads()](ReadCounters& counters) {
                ThreadPool pool(threads);
                return area_line(ds, polygon, filter, pool, counters.watch());
            });
    }

    // The measurement's progress, then its line; true once there is none running.
    bool area_step() {
        if (!area_job_) return true;
        if (!area_job_->done()) return void(panels_.click.area = "area: " + area_job_->status()), false;
        panels_.click.area = area_job_->status();
        area_job_.reset();
        if (print_area_) std::printf("%s\n", panels_.click.area->c_str()), std::fflush(stdout);
        print_area_ = false;
        return true;
    }

    void save_session(const std::string& path) {
        try {
            write_session(path, current_session());
            panels_.status = "session saved: " + path;
        } catch (const Error& e) {
            panels_.status = e.what();  // one line in the window; the viewer goes on
        }
    }

    double since_start() const { return std::chrono::duration<double>(Clock::now() - start_).count(); }

    // Files dropped on the window start an opening; a finished one replaces the session shown;
    // while the first one opens, the camera follows the tiles read so far.
    void open_step() {
        if (!events_.dropped.empty()) {
            opening_ = start_opening(events_.dropped, o_, !session_.open(), budget_.plan());  // shown until then
            paths_ = events_.dropped;
            events_.dropped.clear();
            if (!session_.open()) {  // (given up)
                footprints_.clear(), preview_.reset(), next_preview_.reset();
                footprint_picture_ = {};
            }
        }
        if (opening_ && opening_->finished()) close_background();  // they read the dataset shown
        if (opening_ && opening_->finished() && take_opening(opening_, session_, panels_)) {
            corrections_shown_ = 0;
            refiner_.invalidate();
            loaded_at_.reset(), opening_over_ = false;  // (a dataset dropped: its opening is forgotten in turn)
            if (!moved_while_opening_) controller_.frame(session_.dataset->bounds_m, fb_width_, fb_height_);
            moved_while_opening_ = false;
            if (!opened_) {
                settings_ = initial_settings(*session_.dataset, budget_.asked(), o_);
                if (o_.session) apply_session(*o_.session);
                if (o_.profile) start_profile(*o_.profile, controller_.target_z);
                opened_ = Clock::now();
                times_.dataset_open_s = since_start();
            }
        }
        if (!session_.open()) {
            const OpeningProgress progress = opening_->progress();
            opening_->footprints(footprints_);
            every_footprint_ = progress.total > 0 && footprints_.size() >= progress.total;
            if (auto latest = opening_->preview(); latest && latest != preview_ && latest != next_preview_) {
                (preview_ ? next_preview_ : preview_) = std::move(latest);  // (a paged catalog's grows)
                if (!next_preview_) preview_settings_ = initial_settings(*preview_->dataset, budget_.asked(), o_);
            }
            if (!moved_while_opening_ && !progress.extent.empty())
                controller_.frame(progress.extent, fb_width_, fb_height_);
        } else {  // the tiles whose headers corrected their items, named as they are read
            const Diagnostics corrections = session_.dataset->corrections(corrections_shown_);
            corrections_shown_ += corrections.size();
            print_warnings(corrections);
        }
    }

    void input_step(double dt) {
        const CameraController before = controller_;
        input_.apply(win_.window, events_, controller_, dt, fb_height_);
        if (!session_.open() && !(controller_ == before)) moved_while_opening_ = true;
    }

    // The picture (the dataset's, or the footprints while it opens), a click's pick, the cursor readout.
    void draw_step(Clock::time_point now) {
        with_heightmaps_ = false;
        if (next_preview_ && session_.open()) next_preview_.reset();
        if (next_preview_) {  // a paged catalog's larger preview: shown once it draws as much as the one shown
            next_preview_->scheduler->set_camera(camera_);
            if (next_preview_->scheduler->snapshot()->heightmaps.size() >= preview_heightmaps_) {
                preview_ = std::move(next_preview_);
                preview_settings_ = initial_settings(*preview_->dataset, budget_.asked(), o_);
                refiner_.invalidate();
            }
        }
        if (preview_ && session_.open()) {
            session_.scheduler->set_camera(camera_);
            drawn_ = session_.scheduler->snapshot();  // for the panels
            if (!drawn_->heightmaps.empty() && drawn_->heightmaps.size() >= preview_heightmaps_) {
                preview_.reset();  // the dataset's own terrain shows as much: the preview ends
                refiner_.invalidate();
            }
        }
        if (preview_) {  // a large catalog's centre among every footprint, until the dataset draws as much
            std::shared_ptr<const SceneSnapshot> shown;
            draw_frame(*preview_, controller_, preview_settings_, panels_, fb_width_, fb_height_, pool_, refiner_,
                       camera_, shown, last_);
            draw_footprints(last_.image, camera_, footprints_, render::pack_rgba(255, 200, 40));
            with_heightmaps_ = !shown->heightmaps.empty();
            preview_heightmaps_ = shown->heightmaps.size();
        } else if (session_.open()) {
            draw_frame(session_, controller_, settings_, panels_, fb_width_, fb_height_, pool_, refiner_, camera_,
                       drawn_, last_);
            with_heightmaps_ = !drawn_->heightmaps.empty();
            draw_profile_corridor();
        } else {
            last_ = opening_frame(footprints_, controller_, fb_width_, fb_height_, camera_, footprint_picture_);
        }
        frame_ms_ = 1000.0 * std::chrono::duration<double>(Clock::now() - now).count();
        if (const auto click = input_.take_click(); click && session_.open()) {
            pick_at_click(win_.window, *click, session_, camera_, settings_.style.filter, panels_);
            profile_after_click();
        }
        panels_.cursor =
            session_.open() ? cursor_text(win_.window, *session_.cursor, camera_, controller_.target_z) : "";
    }

    // The image and the panels on the window.
    // (A frame that changes nothing the window shows is not presented again: viewer/frame_change.hpp.)
    PanelActions present_step() {
        ImGui_ImplOpenGL3_NewFrame();
        ImGui_ImplGlfw_NewFrame();
        ImGui::NewFrame();
        PanelActions actions;
        SchedulerStats stats;
        if (session_.open()) {
            stats = session_.scheduler->stats();
            panels_.loaded_classes = loaded_class_counts(*drawn_);
            profile_step();
            export_step();
            area_step();
            if (!budget_note_.empty()) stats.notes.push_back(budget_note_);
            if (!overview_note_.empty()) stats.notes.push_back(overview_note_);
            actions = draw_panels(*session_.dataset, stats, frame_ms_, settings_, panels_);
            draw_labels(panels_.annotations, camera_);
        }
        if (opening_) draw_opening_panel(opening_->progress());
        ImGui::Render();
        const std::uint64_t panels = fingerprint(*ImGui::GetDrawData(), profile_uploads_);
        if (!o_.window_screenshot.empty() ||
            frame_change_.present(last_.image, panels, fb_width_, fb_height_, Clock::now(), at_panels())) {
            glViewport(0, 0, fb_width_, fb_height_);
            glClearColor(0, 0, 0, 1);
            glClear(GL_COLOR_BUFFER_BIT);
            presenter_.show(last_.image, fb_width_, fb_height_);
            ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
            if (!o_.window_screenshot.empty()) window_shot_ = window_pixels(win_.window);  // scripted use only
            glfwSwapBuffers(win_.window);
        }
        count_frame(times_, session_, stats, every_footprint_, with_heightmaps_, since_start());
        return actions;
    }

    // Whether the user is at the window this frame: the mouse moving or scrolled, a button or key down, text typed.
    static bool at_panels() {
        const ImGuiIO& io = ImGui::GetIO();
        const bool moved = io.MouseDelta.x != 0 || io.MouseDelta.y != 0 || io.MouseWheel != 0 || io.MouseWheelH != 0;
        const bool down = std::any_of(std::begin(io.MouseDown), std::end(io.MouseDown), [](bool d) { return d; });
        return moved || down || !io.InputQueueCharacters.empty() || ImGui::IsAnyItemActive() ||
               ImGui::IsKeyDown(ImGuiKey_Enter) || ImGui::IsKeyDown(ImGuiKey_Backspace) ||
               ImGui::IsKeyDown(ImGuiKey_Tab) || ImGui::IsKeyDown(ImGuiKey_Escape);
    }

    void action_step(const PanelActions& actions) {
        if (actions.fly_to) {
            controller_.frame(session_.dataset->tiles[*actions.fly_to].bounds_m, fb_width_, fb_height_);
        }
        if (actions.budget_changed) budget_.set_asked(std::uint64_t(settings_.budget_mb) << 20), apply_budget();
        if (actions.save_session) save_session(panels_.session_path);
        if (actions.measure_area) measure_area_now();
        profile_actions(actions);
        if (actions.export_clip) start_export(panels_.exports.clip_path, io::OutputKind::PointCloud, [&] {
            return export_clip(*session_.dataset, panels_.exports.clip_path, area_region(), settings_.style.filter,
                               job_threads());
        });
        if (actions.cancel_export && export_) export_->cancel();
        if (actions.screenshot || input_.pressed(win_.window, GLFW_KEY_F12)) {  // the picture without the panels
            const std::string name = screenshot_name();
            render::write_png(name, last_.image);
            panels_.status = "screenshot: " + name;
        }
    }

    // --quit-after: the scripted clicks, a few frames to show them, then true (quit).
    bool script_step() {
        const bool quitting = opened_ && o_.quit_after > 0 &&
                              std::chrono::duration<double>(Clock::now() - *opened_).count() >= o_.quit_after;
        if (quitting && !scripted_clicks_done_) {
            panels_.click.use(o_.area ? ClickTool::Area : o_.measure ? ClickTool::Measure : ClickTool::Inspect);
            for (const auto& c : o_.clicks) {
                pick_at_click(win_.window, c, session_, camera_, settings_.style.filter, panels_);
                print_click(c, *session_.dataset, panels_.click);
            }
            pending_clip_out_ = !o_.clip_out.empty();
            if (o_.area) measure_area_now(), print_area_ = true;  // printed once measured
            scripted_clicks_done_ = true;
            frames_to_quit_ = 3;  // a new ImGui window fits its size in its first frame, unseen
        }
        return quitting && scripted_outputs_done() && frames_to_quit_-- <= 0;
    }

    unsigned job_threads() const { return std::max(1u, std::thread::hardware_concurrency()); }

    // The process's budget kept (viewer/process_budget.hpp): a few times a second what the process holds
    // beyond the scheduler's ledger is measured and the scheduler's share set from it. (The residency
    // returns freed pages to the system where it releases or decodes: no trim here, on the frame's thread.)
    void budget_step() {
        if (!session_.open() || !budget_tick_.due(1)) return;
        budget_tick_.done();
        const SchedulerStats st = session_.scheduler->stats();
        opening_step(st);
        budget_.observe(resident_bytes(), st.bytes_used);
        session_.scheduler->set_network_room(budget_.network_leaves_room(st.overview_core_bytes));
        if (st.network_declined && !budget_.declined()) {  // (its line written once)
            budget_.network_declined();
            std::fprintf(stderr, "lidarscout: %s\n", network_declined_note(st.tiles).c_str());
        }
        apply_budget();
        report_overview_note(st);
        overview_cache_step(st);
    }

    // What the opening held beyond the data (a country's catalog blocks and sidecar buffers: ~250 MB) forgotten
    // by the budget a second after every tile's chunk points are in (and the grid's spare room given back).
    void opening_step(const SchedulerStats& st) {
        if (opening_over_ || st.tiles_loaded.done < st.tiles_loaded.total) return;
        const auto now = Clock::now();
        if (!loaded_at_) loaded_at_ = now;
        if (now - *loaded_at_ < std::chrono::seconds(1)) return;
        budget_.opening_over();
        opening_over_ = true;
    }

    // The overview sidecar kept for a remote dataset: written once every tile's chunk points are in, and the
    // line saying why it was not, on stderr.
    void overview_cache_step(const SchedulerStats& st) {
        const auto& cache = session_.overview_cache;
        if (!cache) return;
        cache->write_when_loaded(*session_.dataset, st.tiles_loaded.done >= st.tiles_loaded.total);
        if (const auto note = cache->take_note(); note && !note->empty()) {
            std::fprintf(stderr, "lidarscout: %s\n", note->c_str());
        }
    }

    // The line saying the overview leaves full resolution no room: on stderr the first time, in the panel
    // while it holds (a larger budget clears it).
    void report_overview_note(const SchedulerStats& st) {
        overview_note_ = overview_fills_note(st.bytes_used - st.bytes_full_res - st.bytes_decoding,
                                             st.memory_budget, st.tiles);
        // (on stderr only once the opening is over: its buffers, forgotten then, may have been all that filled it)
        if (overview_note_.empty() || !opening_over_ || std::exchange(said_overview_, true)) return;
        std::fprintf(stderr, "lidarscout: %s\n", overview_note_.c_str());
    }

    void apply_budget() {
        if (!session_.open()) return;
        const ProcessBudgetPlan plan = budget_.plan();
        const std::uint64_t now = session_.scheduler->stats().memory_budget;
        if ((plan.data > now ? plan.data - now : now - plan.data) >= (1u << 20)) {
            session_.scheduler->set_memory_budget(plan.data);
        }
        if (budget_note_.empty() || (plan.below && !said_below_)) report_budget_note(plan);
        budget_note_ = plan.note;
    }

    // The line saying the budget is below what the viewer needs (or leaves the network out), on stderr once
    // of each kind: a budget found below it later, as the program's share grows, is said too (the panel's
    // notes keep the line, its figures kept up to date).
    void report_budget_note(const ProcessBudgetPlan& plan) {
        if (!plan.note.empty()) std::fprintf(stderr, "lidarscout: %s\n", plan.note.c_str());
        budget_note_ = plan.note;
        said_below_ = said_below_ || plan.below;
    }

    // The memory figures of the run (ViewerTimings).
    void memory_figures() {
        times_.peak_resident_bytes = peak_resident_bytes();
        times_.budget_bytes = budget_.asked();
        times_.outside_bytes = budget_.outside();
        times_.budget_note = budget_note_;
        times_.overview_note = overview_note_;
        if (!session_.open()) return;
        const SchedulerStats st = session_.scheduler->stats();
        times_.ledger_peak_bytes = st.peak_bytes_used;
        times_.data_budget_bytes = st.memory_budget;
    }

    // The profiles and exports read the dataset shown: ended (cancelled) before it is replaced.
    void close_background() {
        profile_.reset();
        retired_.clear();
        export_.reset();
        area_job_.reset();
        panels_.exports.running = false;
    }

    // Opens a profile (replacing, so cancelling, the one shown); `z` (world metres) is where its
    // corridor is drawn until points show the ground.
    void start_profile(const pipelines::Corridor& c, double z) {
        retire_profile();
        profile_ = std::make_unique<ProfileJob>(*session_.dataset, c, settings_.style.filter, profile_look(),
                                                job_threads());
        profile_seen_ = 0, profile_z_ = z;
        auto& p = panels_.profile;
        p.texture = 0, p.texture_width = p.texture_height = 0;
        const double f = session_.dataset->frame.xy_to_metres;
        PickedPoint start;  // the units of the first tile (the frame's, for tiles reprojected into it)
        start.x = c.x0 * f, start.y = c.y0 * f, start.tile = 0;
        const PointReadout units = point_readout(*session_.dataset, start);
        p.unit = units.horizontal_unit;
        char title[256];
        std::snprintf(title, sizeof title, "%.3f, %.3f to %.3f, %.3f: %.1f long, %.2f wide (%s)", c.x0, c.y0, c.x1,
                      c.y1, c.length(), c.width, p.unit.c_str());
        p.title = title;
    }

    // The profile tool's second click opens the profile between the two ends.
    void profile_after_click() {
        const ClickState& click = panels_.click;
        if (click.tool != ClickTool::Profile || click.missed || !click.from || !click.to) return;
        const pipelines::Corridor c =
            corridor_between(*click.from, *click.to, panels_.profile.width, session_.dataset->frame);
        if (!(c.length() > 0)) return void(panels_.status = "profile: the two ends are the same point");
        start_profile(c, (click.from->z + click.to->z) / 2);
    }

    // A profile closed or replaced: its read cancelled, the job ended once the read stops (the frame
    // does not wait for a batch being decoded).
    void retire_profile() {
        if (!profile_) return;
        profile_->cancel();
        retired_.push_back(std::move(profile_));
    }

    ProfileLook profile_look() const {
        ProfileLook look;
        look.colours = panels_.profile.elevation ? pipelines::ProfileColours::Elevation
                                                 : pipelines::ProfileColours::Classification;
        const dataset::Dataset& ds = *session_.dataset;  // the view's ramp: the dataset's heights
        look.ramp_min = ds.bounds_m.min_z / ds.frame.z_to_metres;
        look.ramp_max = ds.bounds_m.max_z / ds.frame.z_to_metres;
        return look;
    }

    // The profile's panel from its job: the newest image, the progress, what the plot spans.
    void profile_step() {
        std::erase_if(retired_, [](const auto& job) { return job->status().done; });
        auto& p = panels_.profile;
        if (settings_.style.colour.mode != view_colours_) {  // coloured like the view: by elevation or by class
            view_colours_ = settings_.style.colour.mode;
            p.elevation = view_colours_ == render::ColourMode::Elevation;
            if (profile_) profile_->set_look(profile_look());
        }
        p.open = profile_ != nullptr;
        if (!profile_) return;
        if (const auto image = profile_->image_since(profile_seen_)) {
            profile_texture_.upload(*image);
            ++profile_uploads_;  // (the panels' draw data alone would not show the plot changed)
            p.texture = profile_texture_.id();
            p.texture_width = profile_texture_.width(), p.texture_height = profile_texture_.height();
        }
        const ProfileStatus st = profile_->status();
        char text[256];
        if (!st.error.empty()) {
            p.status = st.error;
        } else if (!st.done) {
            std::snprintf(text, sizeof text, "reading: %s; %llu points in the corridor", st.read.line().c_str(),
                          (unsigned long long)st.points);
            p.status = text;
        } else {
            std::snprintf(text, sizeof text, "%llu points in the corridor (%s)", (unsigned long long)st.points,
                          st.read.line().c_str());
            p.status = text;
        }
        const pipelines::ProfileImageScale sc = profile_->scale();
        std::snprintf(text, sizeof text, "distance 0 - %.1f left to right (grid every %g), height %.1f - %.1f "
                      "bottom to top (grid every %g), %s", profile_->corridor().length(), sc.distance_step, sc.z_min,
                      sc.z_max, sc.z_step, p.unit.c_str());
        p.axes = sc.distance_step > 0 ? text : "";
        p.filter_changed = !(profile_->filter() == settings_.style.filter);
    }

    void profile_actions(const PanelActions& a) {
        auto& p = panels_.profile;
        if (a.close_profile) retire_profile(), p.open = false;
        if (a.reread_profile && profile_) start_profile(profile_->corridor(), profile_z_);
        if (a.open_kept_profile && *a.open_kept_profile < p.kept.size()) {
            const SavedProfile& k = p.kept[*a.open_kept_profile];
            start_profile({k.line[0], k.line[1], k.line[2], k.line[3], k.width}, controller_.target_z);
        }
        if (a.keep_profile && profile_) {
            const auto& c = profile_->corridor();
            const SavedProfile kept{{c.x0, c.y0, c.x1, c.y1}, c.width};
            if (std::find(p.kept.begin(), p.kept.end(), kept) == p.kept.end()) p.kept.push_back(kept);
        }
        if (a.profile_colours && profile_) profile_->set_look(profile_look());
        if (a.export_profile && profile_) {
            start_export(p.export_path, io::OutputKind::Profile, [&] {
                return export_profile(*session_.dataset, p.export_path, profile_->corridor(), profile_->filter(),
                                      profile_->profile(), job_threads());
            });
        }
    }

    // The profile's corridor over the picture, following the lowest points read along it.
    void draw_profile_corridor() {
        if (!profile_) return;
        const auto& c = profile_->corridor();
        const auto& frame = session_.dataset->frame;
        const double f = frame.xy_to_metres;
        std::vector<double> heights = profile_->line_heights();
        if (!heights.empty() && std::isnan(heights[0])) heights.clear();
        for (auto& z : heights) z *= frame.z_to_metres;
        draw_corridor(last_.image, camera_, {c.x0 * f, c.y0 * f, c.x1 * f, c.y1 * f}, c.width / 2 * f, heights,
                      profile_z_, render::pack_rgba(255, 120, 40));
    }

    // The area tool's polygon as a region in the dataset CRS's units (what it measures); throws lidarscout::Error.
    pipelines::Region area_region() const { return viewer::area_region(*session_.dataset, panels_.click.polygon); }

    // Starts an export (one at a time) after checking its output as the command line would; an error
    // is the status line (and, scripted, an error).
    template <typename Make>
    void start_export(const std::string& path, io::OutputKind kind, Make make) {
        if (export_ && !export_->done()) return void(panels_.status = "an export is running");
        try {
            check_export(path, kind, paths_);
            export_ = make();
            panels_.exports.running = true;
            panels_.exports.status = "writing " + path;
        } catch (const Error& e) {
            panels_.exports.status = e.what();
            if (o_.quit_after > 0) report_failure(e.what());
        }
    }

    // The export's progress, and its end: the result line (on stdout when scripted).
    void export_step() {
        if (!export_) return;
        panels_.exports.status = export_->status();
        if (!export_->done()) return;
        if (export_->failed()) report_failure(export_->status());
        else if (o_.quit_after > 0) std::printf("%s\n", export_->status().c_str()), std::fflush(stdout);
        frames_to_quit_ = std::max(frames_to_quit_, 3);  // scripted: a few frames show the result line
        export_.reset();
        panels_.exports.running = false;
    }

    void report_failure(const std::string& line) {
        if (o_.quit_after <= 0) return;
        std::fprintf(stderr, "lidarscout: %s\n", line.c_str());
        script_status_ = 1;
    }

    // --clip-out (after the clicks) and --profile-out (once the profile is read), one after the
    // other; true when both are written (or failed).
    bool scripted_outputs_done() {
        if (!area_step()) return false;
        if (export_) {
            export_step();
            if (export_) return false;
        }
        if (pending_clip_out_) {
            pending_clip_out_ = false;
            try {
                const pipelines::Region region = area_region();
                std::printf("clip polygon: %s\n", polygon_wkt().c_str());
                start_export(o_.clip_out, io::OutputKind::PointCloud, [&] {
                    return export_clip(*session_.dataset, o_.clip_out, region, settings_.style.filter, job_threads());
                });
            } catch (const Error& e) {
                report_failure(std::string("--clip-out: ") + e.what());
            }
            return false;
        }
        if (pending_profile_out_) {
            if (profile_ && !profile_->status().done) return false;
            pending_profile_out_ = false;
            const std::string error = profile_ ? profile_->status().error : "--profile-out: no profile open";
            if (!error.empty()) {
                report_failure(error);
                return true;
            }
            start_export(o_.profile_out, io::OutputKind::Profile, [&] {
                return export_profile(*session_.dataset, o_.profile_out, profile_->corridor(), profile_->filter(),
                                      profile_->profile(), job_threads());
            });
            return false;
        }
        return true;
    }

    // The area tool's polygon as WKT in the dataset CRS's units, every digit (`lidarscout clip --polygon`).
    std::string polygon_wkt() const {
        const double f = session_.dataset->frame.xy_to_metres;
        std::string wkt = "POLYGON ((";
        char xy[80];
        const auto& ring = panels_.click.polygon;
        for (std::size_t k = 0; k <= ring.size(); ++k) {
            const auto& v = ring[k % ring.size()];
            std::snprintf(xy, sizeof xy, "%s%.17g %.17g", k ? ", " : "", v.x / f, v.y / f);
            wkt += xy;
        }
        return wkt + "))";
    }

    const ViewerOptions& o_;
    std::vector<std::string> paths_ = o_.paths;  // of the dataset shown (or opening)
    const Clock::time_point start_;
    GlfwWindow win_;
    InputEvents events_;
    GuiContext gui_;
    GlPresenter presenter_;
    ThreadPool pool_;
    ProcessBudget budget_;            // measured with the window up, before any dataset
    bool said_below_ = false;         // the line saying the budget is below what the viewer needs was written
    bool said_overview_ = false;      // the overview's line (overview_fills_note) was written
    Throttle budget_tick_{std::chrono::milliseconds(250), 0};
    std::optional<Clock::time_point> loaded_at_;  // every tile's chunk points in (opening_step)
    bool opening_over_ = false;                   // the budget forgot the opening (opening_step)
    std::string budget_note_;         // the budget is below what the viewer needs (shown in the panel)
    std::string overview_note_;       // the overview leaves full resolution no room (overview_fills_note)
    std::unique_ptr<SessionOpening> opening_;
    Session session_;                          // empty until the first dataset is open
    std::vector<dataset::Bounds> footprints_;  // of the tiles read while the first dataset opens
    FootprintPicture footprint_picture_;       // footprints_ drawn (opening_frame)
    std::size_t corrections_shown_ = 0;        // the dataset's corrections (Dataset::corrections) on stderr
    std::shared_ptr<const Session> preview_;   // a large catalog's centre, drawn until the dataset draws
    std::size_t preview_heightmaps_ = 0;       // in its last frame
    std::shared_ptr<const Session> next_preview_;  // a paged catalog's larger preview, until it draws as much
    bool every_footprint_ = false;             // footprints_ holds every tile's (a catalog's, or all read)
    ViewSettings preview_settings_;
    bool moved_while_opening_ = false;         // then the camera stays where the user put it
    CameraController controller_;
    ViewSettings settings_;
    PanelState panels_;
    MouseKeyboard input_;
    RenderedScene last_;
    render::RgbaImage window_shot_;  // --window-screenshot: the last frame with its panels
    FrameRefiner refiner_;
    ViewerTimings times_;
    std::optional<Clock::time_point> opened_;  // when the first dataset opened (--quit-after counts from there)
    Clock::time_point previous_;
    double frame_ms_ = 0;
    bool scripted_clicks_done_;
    int frames_to_quit_ = 0;
    int fb_width_ = 1, fb_height_ = 1;
    render::Camera camera_;
    bool with_heightmaps_ = false;
    std::shared_ptr<const SceneSnapshot> drawn_;  // the snapshot of the last frame drawn
    GlTexture profile_texture_;                   // the profile's plot
    std::uint64_t profile_uploads_ = 0;           // its images uploaded (in the panels' fingerprint)
    FrameChange frame_change_;                    // whether a frame changes what the window shows
    // Last: they read session_'s dataset, so they end (cancelled) before it goes.
    std::unique_ptr<ProfileJob> profile_;
    std::vector<std::unique_ptr<ProfileJob>> retired_;  // closed, ended once their reads stop
    std::uint64_t profile_seen_ = 0;  // the generation of the profile image uploaded
    double profile_z_ = 0;            // where its corridor is drawn until points show the ground
    render::ColourMode view_colours_ = render::ColourMode::Rgb;  // the view's, which the profile's follow
    std::unique_ptr<ExportTask> export_;
    std::unique_ptr<ExportTask> area_job_;  // the area tool's measurement (its line, no file)
    bool print_area_ = false;               // scripted: the measurement's line printed once made
    bool pending_clip_out_ = false, pending_profile_out_ = !o_.profile_out.empty();
    int script_status_ = 0;
};

}  // namespace

int run_viewer(const ViewerOptions& o, ViewerTimings* timings) {
    // A remote path's first request goes out while the window opens (a software OpenGL's start takes a tenth of a
    // second, a new connection two round trips): its opening finds it open. A catalog's first blocks too, its open
    // being the first block's request (a country's 250 MB had waited for the window, then for an open's two requests
    // of a tile's edges, before its first was asked for).
    const auto is_catalog = [](const std::string& p) {
        return dataset::is_stac_catalog(p) && !dataset::is_virtual_replica(p);
    };
    std::vector<std::string> others;
    std::copy_if(o.paths.begin(), o.paths.end(), std::back_inserter(others),
                 [&](const std::string& p) { return !is_catalog(p); });
    io::File::prefetch(others);
    const auto catalog = std::find_if(o.paths.begin(), o.paths.end(), is_catalog);
    if (catalog != o.paths.end()) dataset::prefetch_json_document(*catalog);
    struct ForgetOnLeaving {  // (blocks no opening took are not read on after the window closed)
        ~ForgetOnLeaving() { dataset::forget_json_prefetch(); }
    } forget_on_leaving;
    ViewerLoop loop(o);
    while (loop.frame()) {
    }
    return loop.finish(timings);
}

}  // namespace lidarscout::viewer::app
