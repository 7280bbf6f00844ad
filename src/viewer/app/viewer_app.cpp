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
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <memory>
#include <thread>
#include <utility>

#include "core/error.hpp"
#include "core/thread_pool.hpp"
#include "dataset/dataset.hpp"
#include "render/resolve.hpp"
#include "render/png_writer.hpp"
#include "viewer/app/camera_controller.hpp"
#include "viewer/app/gl_presenter.hpp"
#include "viewer/app/overlay.hpp"
#include "viewer/app/panels.hpp"
#include "viewer/cursor_readout.hpp"
#include "viewer/frame_refiner.hpp"
#include "viewer/picking.hpp"
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

// Starts opening `paths` in the background (viewer/session_opening.hpp).
std::unique_ptr<SessionOpening> start_opening(const std::vector<std::string>& paths, const ViewerOptions& o) {
    SessionOptions so;
    so.crs = o.crs;
    so.scheduler.memory_budget = o.memory_budget;
    so.scheduler.cnn = o.cnn;
    so.scheduler.model_path = o.model;
    return std::make_unique<SessionOpening>(paths, std::move(so));
}

// Puts the finished opening's session in place of the one shown. An error ends the viewer when
// nothing is shown yet (the first dataset), else it is the status line. True when replaced.
bool take_opening(std::unique_ptr<SessionOpening>& opening, Session& session, PanelState& panels) {
    const auto finished = std::move(opening);
    try {
        Session next = finished->take();
        session.scheduler.reset();  // it reads the dataset it replaces
        session = std::move(next);
        panels = {};
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
                   const render::Camera& camera, PanelState& panels) {
    int win_width = 1, win_height = 1;
    glfwGetWindowSize(window, &win_width, &win_height);
    const double sx = static_cast<double>(camera.width) / std::max(1, win_width);
    const double sy = static_cast<double>(camera.height) / std::max(1, win_height);
    PickOptions options;
    options.radius_px = std::max(2.0, 4 * sx);
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
    const auto& point = click.tool == ClickTool::Measure ? (click.to ? click.to : click.from) : click.picked;
    if (click.missed || !point) std::printf("click %.0f,%.0f: no point\n", at.first, at.second);
    else std::printf("click %.0f,%.0f: %s\n", at.first, at.second, point_summary(ds, *point).c_str());
    if (!click.missed && click.from && click.to) {
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

ViewSettings initial_settings(const dataset::Dataset& ds, const SchedulerStats& stats, render::Backend backend) {
    ViewSettings v;
    v.style.backend = backend;
    v.style.colour = colour_settings(render::ColourMode::Rgb, ds.bounds_m.min_z, ds.bounds_m.max_z);
    v.budget_mb = static_cast<int>(std::min<std::uint64_t>(stats.memory_budget >> 20, 1u << 30));
    return v;
}

// The frame's picture: the snapshot drawn at the render scale, then the tile outlines;
// `with_heightmaps` tells whether the snapshot had any.
RenderedScene draw_frame(const Session& s, const CameraController& controller, const ViewSettings& v,
                         const PanelState& panels, int fb_width, int fb_height, ThreadPool& pool,
                         FrameRefiner& refiner, render::Camera& camera, bool& with_heightmaps) {
    const int w = std::max(1, static_cast<int>(std::lround(fb_width * v.render_scale)));
    const int h = std::max(1, static_cast<int>(std::lround(fb_height * v.render_scale)));
    camera = controller.camera(w, h);
    s.scheduler->set_camera(camera);
    SceneStyle style = v.style;
    style.colour = colour_settings(v.style.colour.mode, s.dataset->bounds_m.min_z, s.dataset->bounds_m.max_z);
    const bool loading = s.scheduler->points_loading();  // before the snapshot: when false, it holds all
    const auto snapshot = s.scheduler->snapshot();
    RenderedScene frame = refiner.draw(*snapshot, camera, style, pool, v.layers, loading);
    with_heightmaps = !snapshot->heightmaps.empty();
    if (v.tile_boxes) {
        draw_tile_boxes(frame.image, camera, *s.dataset, *s.places, render::pack_rgba(255, 200, 40), panels.selected);
    }
    draw_click_overlay(frame.image, camera, panels.click);
    return frame;
}

// The picture while the first dataset opens: the footprints of the tiles read so far.
RenderedScene opening_frame(std::span<const dataset::Bounds> footprints, const CameraController& controller,
                            int width, int height, render::Camera& camera) {
    camera = controller.camera(width, height);
    RenderedScene frame;
    frame.image.width = width, frame.image.height = height;
    frame.image.pixels.assign(static_cast<std::size_t>(width) * height, render::ResolveSettings{}.background);
    draw_footprints(frame.image, camera, footprints, render::pack_rgba(255, 200, 40));
    return frame;
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

// Notes the times of the first frame presented, of the first with a heightmap, and of the first
// with every tile's chunk points in (`stats`: the scheduler's, taken for this frame's panels).
void count_frame(ViewerTimings& t, const Session& session, const SchedulerStats& stats, bool with_heightmaps,
                 double seconds) {
    if (!t.first_frame_s) t.first_frame_s = seconds;
    if (!session.open()) {
        ++t.frames_while_opening;
        return;
    }
    if (!t.first_overview_s && with_heightmaps) t.first_overview_s = seconds;
    if (!t.chunk_points_s && stats.tiles_loaded.done == stats.tiles_loaded.total) t.chunk_points_s = seconds;
}

}  // namespace

int run_viewer(const ViewerOptions& o, ViewerTimings* timings) {
    const auto start = Clock::now();
    const auto since_start = [&start] { return std::chrono::duration<double>(Clock::now() - start).count(); };
    GlfwWindow win(o.width, o.height, "lidarscout");
    InputEvents events;
    install_callbacks(win.window, events);
    GuiContext gui(win.window);
    GlPresenter presenter;
    ThreadPool pool(o.threads ? o.threads : std::max(1u, std::thread::hardware_concurrency()));

    std::unique_ptr<SessionOpening> opening = start_opening(o.paths, o);
    Session session;                         // empty until the first dataset is open
    std::vector<dataset::Bounds> footprints;  // of the tiles read while the first dataset opens
    bool moved_while_opening = false;        // then the camera stays where the user put it
    CameraController controller;
    ViewSettings settings;
    PanelState panels;
    MouseKeyboard input;
    RenderedScene last;
    render::RgbaImage window_shot;  // --window-screenshot: the last frame with its panels
    FrameRefiner refiner;
    ViewerTimings times;
    std::optional<Clock::time_point> opened;  // when the first dataset opened (--quit-after counts from there)
    auto previous = start;
    double frame_ms = 0;
    bool scripted_clicks_done = o.clicks.empty() && !o.measure;
    int frames_to_quit = 0;
    while (!glfwWindowShouldClose(win.window)) {
        glfwPollEvents();
        const auto now = Clock::now();
        const double dt = std::chrono::duration<double>(now - previous).count();
        previous = now;
        int fb_width = 0, fb_height = 0;
        glfwGetFramebufferSize(win.window, &fb_width, &fb_height);
        fb_width = std::max(1, fb_width), fb_height = std::max(1, fb_height);
        if (!events.dropped.empty()) {
            opening = start_opening(events.dropped, o);  // the dataset shown stays until it is open
            events.dropped.clear();
        }
        if (opening && opening->finished() && take_opening(opening, session, panels)) {
            refiner.invalidate();
            if (!moved_while_opening) controller.frame(session.dataset->bounds_m, fb_width, fb_height);
            moved_while_opening = false;
            if (!opened) {
                settings = initial_settings(*session.dataset, session.scheduler->stats(), o.backend);
                opened = Clock::now();
                times.dataset_open_s = since_start();
            }
        }
        if (!session.open()) {
            const OpeningProgress progress = opening->progress();
            opening->footprints(footprints);
            const bool follow = !moved_while_opening && !progress.extent.empty();
            if (follow) controller.frame(progress.extent, fb_width, fb_height);
        }
        const CameraController before = controller;
        input.apply(win.window, events, controller, dt, fb_height);
        if (!session.open() && !(controller == before)) moved_while_opening = true;
        render::Camera camera;
        bool with_heightmaps = false;
        if (session.open()) {
            last = draw_frame(session, controller, settings, panels, fb_width, fb_height, pool, refiner, camera,
                              with_heightmaps);
        } else {
            last = opening_frame(footprints, controller, fb_width, fb_height, camera);
        }
        frame_ms = 1000.0 * std::chrono::duration<double>(Clock::now() - now).count();
        if (const auto click = input.take_click(); click && session.open()) {
            pick_at_click(win.window, *click, session, camera, panels);
        }
        panels.cursor = session.open() ? cursor_text(win.window, *session.cursor, camera, controller.target_z) : "";

        glViewport(0, 0, fb_width, fb_height);
        glClearColor(0, 0, 0, 1);
        glClear(GL_COLOR_BUFFER_BIT);
        presenter.show(last.image, fb_width, fb_height);
        ImGui_ImplOpenGL3_NewFrame();
        ImGui_ImplGlfw_NewFrame();
        ImGui::NewFrame();
        PanelActions actions;
        SchedulerStats stats;
        if (session.open()) {
            stats = session.scheduler->stats();
            actions = draw_panels(*session.dataset, stats, frame_ms, settings, panels);
        }
        if (opening) draw_opening_panel(opening->progress());
        ImGui::Render();
        ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
        if (!o.window_screenshot.empty()) window_shot = window_pixels(win.window);  // scripted use only
        glfwSwapBuffers(win.window);
        count_frame(times, session, stats, with_heightmaps, since_start());
        if (!session.open()) wait_for_next_frame(now);  // cheap frames: leave the cores to the reads

        if (actions.fly_to) {
            controller.frame(session.dataset->tiles[*actions.fly_to].bounds_m, fb_width, fb_height);
        }
        if (actions.budget_changed) session.scheduler->set_memory_budget(std::uint64_t(settings.budget_mb) << 20);
        if (actions.screenshot || input.pressed(win.window, GLFW_KEY_F12)) {  // the picture without the panels
            const std::string name = screenshot_name();
            render::write_png(name, last.image);
            panels.status = "screenshot: " + name;
        }
        const bool quitting =
            opened && o.quit_after > 0 && std::chrono::duration<double>(Clock::now() - *opened).count() >= o.quit_after;
        if (quitting && !scripted_clicks_done) {  // the clicks, then a few frames to show them
            panels.click.use(o.measure ? ClickTool::Measure : ClickTool::Inspect);
            for (const auto& c : o.clicks) {
                pick_at_click(win.window, c, session, camera, panels);
                print_click(c, *session.dataset, panels.click);
            }
            scripted_clicks_done = true;
            frames_to_quit = 3;  // a new ImGui window fits its size in its first frame, unseen
        }
        if (quitting && frames_to_quit-- <= 0) break;
    }
    opening.reset();  // a window closed while opening: cancel the reads not started
    if (session.open()) times.tiles = session.dataset->tiles.size(), times.skipped = session.dataset->skipped.size();
    if (timings) *timings = times;
    if (!o.screenshot.empty()) render::write_png(o.screenshot, last.image);
    if (!o.window_screenshot.empty()) render::write_png(o.window_screenshot, window_shot);
    return 0;
}

}  // namespace lidarscout::viewer::app
