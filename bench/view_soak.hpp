// The soak of `bench_view --soak MINUTES` (issue 55): the viewer's scheduler and renderer for minutes
// (an hour) over a dataset while a scripted user tours it and acts, to show a leak or a slow growth.
// The tour flies back and forth between high above the dataset and 200 m over it (viewer/flight_path
// .hpp), turning 90 degrees each pass; every --soak-action-every seconds (default 15) the next action
// of a fixed cycle: a ground filter (heightmaps laid over as bare earth), every point again, the next
// colour mode, a profile (viewer/profile_tool.hpp, its own thread, dropped at the next profile), an
// area and volume measure (viewer/area_tool.hpp, its own thread), both on the tile nearest the point
// looked at, half the memory budget, the budget back. Frames are drawn back to back at 1280 x 720 as
// the viewer draws them. Every second a row of the CSV: seconds, resident MB, heap in use and kept MB,
// the scheduler's MB against its budget, frames, their median and worst ms, full-resolution tiles,
// loads, releases, errors, and the last action. The summary: the median resident size over the window
// after the warm-up (5 minutes, or a twelfth of a shorter soak) against the median over the last window
// as long, frames over 100 ms beyond the first 5 s after the start or a budget change, errors.
// scripts/plot_soak.sh draws the CSV (gnuplot).
#pragma once

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "core/error.hpp"
#include "core/point_filter.hpp"
#include "core/process_memory.hpp"
#include "core/thread_pool.hpp"
#include "dataset/dataset.hpp"
#include "render/colour_modes.hpp"
#include "viewer/area_tool.hpp"
#include "viewer/flight_path.hpp"
#include "viewer/frame_refiner.hpp"
#include "viewer/patch_heightmap.hpp"
#include "viewer/profile_tool.hpp"
#include "viewer/scene.hpp"
#include "viewer/scheduler.hpp"

namespace lidarscout::bench {

struct SoakSettings {
    double minutes = 60;
    std::string csv = "soak.csv";
    double action_every_s = 15;
    double pass_s = 60;            // one pass of the tour: down from high above, or back up
    std::uint64_t budget = 1ull << 30;
    unsigned threads = 1;          // render threads
    bool cnn = false;
    viewer::SceneStyle style;
};

// The tour's camera at `seconds`: passes down and up between t = 0.2 and t = 1 of the flight path,
// each pair of passes turned 90 degrees from the last.
inline render::Camera soak_camera(const dataset::Bounds& bounds, double seconds, double pass_s) {
    const double passes = seconds / pass_s;
    const auto pass = static_cast<std::uint64_t>(passes);
    const double along = passes - static_cast<double>(pass);
    viewer::FlightPath path;
    path.yaw_deg = 45 + 90.0 * static_cast<double>((pass / 2) % 4);
    const double t = pass % 2 == 0 ? along : 1 - along;
    return viewer::flight_camera(bounds, 0.2 + 0.8 * t, path);
}

// The user's actions, one at a time in a fixed cycle; what they start runs beside the frames.
class SoakActions {
public:
    SoakActions(const dataset::Dataset& ds, viewer::Scheduler& scheduler, viewer::SceneStyle& style,
                std::uint64_t budget)
        : ds_(ds), scheduler_(scheduler), style_(style), budget_(budget) {}
    ~SoakActions() { finish_area(); }
    SoakActions(const SoakActions&) = delete;
    SoakActions& operator=(const SoakActions&) = delete;

    // Does the next action for `camera`; its name. Sets budget_changed when it changed the budget.
    std::string next(const render::Camera& camera, bool& budget_changed) {
        budget_changed = false;
        switch (step_++ % 7) {
            case 0: return set_filter(PointFilter::parse("2", "", ""), "filter ground");
            case 1: return set_filter(PointFilter(), "filter all");
            case 2: return next_colour();
            case 3: return open_profile(camera);
            case 4: return measure_area(camera);
            case 5: budget_changed = true; return set_budget(budget_ / 2, "budget half");
            default: budget_changed = true; return set_budget(budget_, "budget back");
        }
    }
    std::uint64_t failures() const { return failures_; }

private:
    std::string set_filter(const PointFilter& filter, const char* name) {
        style_.filter = filter;
        scheduler_.set_surface(viewer::surface_of(filter));
        return name;
    }
    std::string next_colour() {
        const render::ColourMode modes[] = {render::ColourMode::Rgb, render::ColourMode::Elevation,
                                            render::ColourMode::Intensity, render::ColourMode::Classification};
        const auto mode = modes[colour_++ % 4];
        style_.colour = viewer::colour_settings(mode, ds_.bounds_m.min_z, ds_.bounds_m.max_z);
        return "colour " + std::string(render::colour_mode_name(mode));
    }
    // The centre of the tile nearest the point looked at (a replica's grid has gaps between its
    // tiles), moved `dx` metres east and `dy` north.
    viewer::PickedPoint ground(const render::Camera& camera, double dx, double dy) const {
        const auto [x, y] = viewer::Scheduler::look_at_ground(camera, ds_.bounds_m);
        const auto nearest = std::min_element(ds_.tiles.begin(), ds_.tiles.end(), [&](const auto& a, const auto& b) {
            return a.bounds_m.distance_xy(x, y) < b.bounds_m.distance_xy(x, y);
        });
        viewer::PickedPoint p;
        p.x = nearest->bounds_m.centre_x() + dx, p.y = nearest->bounds_m.centre_y() + dy;
        p.z = 0.5 * (nearest->bounds_m.min_z + nearest->bounds_m.max_z);
        return p;
    }
    std::string open_profile(const render::Camera& camera) {
        if (profile_ && !profile_->status().error.empty()) {
            fmt::print(stderr, "soak: profile: {}\n", profile_->status().error);
            ++failures_;
        }
        profile_.reset();  // (cancels and joins the last one)
        const double width = 2 / ds_.frame.xy_to_metres;
        const auto corridor = viewer::corridor_between(ground(camera, -100, 0), ground(camera, 100, 0), width,
                                                       ds_.frame);
        profile_ = std::make_unique<viewer::ProfileJob>(ds_, corridor, style_.filter, viewer::ProfileLook{}, 1);
        return "profile";
    }
    std::string measure_area(const render::Camera& camera) {
        finish_area();
        std::vector<viewer::PickedPoint> square = {ground(camera, -50, -50), ground(camera, 50, -50),
                                                   ground(camera, 50, 50), ground(camera, -50, 50)};
        area_ = std::thread([this, square = std::move(square), filter = style_.filter] {
            ThreadPool pool(1);
            try {
                viewer::measure_area(ds_, square, filter, pool);
            } catch (const Error& e) {
                area_error_ = e.what();
            }
        });
        return "area";
    }
    void finish_area() {
        if (!area_.joinable()) return;
        area_.join();
        if (!area_error_.empty()) fmt::print(stderr, "soak: {}\n", area_error_), ++failures_;
        area_error_.clear();
    }
    std::string set_budget(std::uint64_t bytes, const char* name) {
        scheduler_.set_memory_budget(bytes);
        return name;
    }

    const dataset::Dataset& ds_;
    viewer::Scheduler& scheduler_;
    viewer::SceneStyle& style_;
    const std::uint64_t budget_;
    std::uint64_t step_ = 0, colour_ = 0, failures_ = 0;
    std::unique_ptr<viewer::ProfileJob> profile_;
    std::thread area_;
    std::string area_error_;  // what the last measure threw
};

// One second's figures, a row of the CSV.
struct SoakSample {
    double t = 0;
    std::vector<double> frame_ms;
};

inline double soak_median(std::vector<double> v) {
    if (v.empty()) return 0;
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
    return v[v.size() / 2];
}

inline void write_soak_row(std::FILE* csv, const SoakSample& s, const viewer::SchedulerStats& st,
                           const std::string& action) {
    const HeapUse heap = heap_use();
    const auto worst = s.frame_ms.empty() ? 0.0 : *std::max_element(s.frame_ms.begin(), s.frame_ms.end());
    fmt::print(csv, "{:.1f},{:.1f},{:.1f},{:.1f},{:.1f},{:.1f},{},{:.1f},{:.1f},{},{},{},{},{}\n", s.t,
               static_cast<double>(resident_bytes()) / (1 << 20), static_cast<double>(heap.in_use) / (1 << 20),
               static_cast<double>(heap.free_kept) / (1 << 20), static_cast<double>(st.bytes_used) / (1 << 20),
               static_cast<double>(st.memory_budget) / (1 << 20), s.frame_ms.size(), soak_median(s.frame_ms), worst,
               st.full_res_tiles, st.full_res_loads, st.full_res_released, st.errors.size(), action);
    std::fflush(csv);
}

// The median of the values sampled in [from, to) seconds (0 when none).
inline double window_median(const std::vector<std::pair<double, double>>& samples, double from, double to) {
    std::vector<double> v;
    for (const auto& [t, value] : samples) {
        if (t >= from && t < to) v.push_back(value);
    }
    return soak_median(std::move(v));
}

// What the summary says, gathered while the soak runs.
struct SoakTotals {
    std::uint64_t frames = 0, slow_frames = 0;  // slow: over 100 ms beyond 5 s of the start or a budget change
    std::vector<std::pair<double, double>> rss_mb;  // (seconds, resident MB), a sample a second
    double rss_max_after_mb = 0;
    std::size_t errors = 0;
};

// Runs the soak over `ds`; prints the summary; 0 when it held (growth under 2%, no slow frame, no
// error), else 1.
inline int run_soak(const dataset::Dataset& ds, SoakSettings s) {
    using Clock = std::chrono::steady_clock;
    std::FILE* csv = std::fopen(s.csv.c_str(), "w");
    if (!csv) throw Error(s.csv, std::nullopt, "cannot write the soak's CSV");
    fmt::print(csv, "seconds,rss_mb,heap_in_use_mb,heap_kept_mb,scheduler_mb,budget_mb,frames,median_ms,worst_ms,"
                    "full_res_tiles,loads,releases,errors,action\n");
    viewer::SchedulerOptions so;
    so.cnn = s.cnn;
    so.memory_budget = s.budget;
    so.camera = soak_camera(ds.bounds_m, 0, s.pass_s);
    viewer::Scheduler scheduler(ds, so);
    viewer::FrameRefiner refiner;
    ThreadPool pool(s.threads);
    SoakActions actions(ds, scheduler, s.style, s.budget);
    const double total_s = 60 * s.minutes, warm_s = std::min(300.0, total_s / 12);
    const auto start = Clock::now();
    const auto seconds = [&] { return std::chrono::duration<double>(Clock::now() - start).count(); };
    SoakTotals totals;
    SoakSample sample;
    std::string action = "start";
    double next_action = s.action_every_s, next_sample = 1, quiet_from = 5;
    for (double t = 0; t < total_s; t = seconds()) {
        const auto camera = soak_camera(ds.bounds_m, t, s.pass_s);
        if (t >= next_action) {
            bool budget_changed = false;
            action = actions.next(camera, budget_changed);
            if (budget_changed) quiet_from = t + 5;
            next_action += s.action_every_s;
        }
        const auto f0 = Clock::now();
        scheduler.set_camera(camera);
        refiner.draw(*scheduler.snapshot(), camera, s.style, pool);
        const double ms = 1000 * std::chrono::duration<double>(Clock::now() - f0).count();
        sample.frame_ms.push_back(ms);
        ++totals.frames;
        if (ms > 100 && t >= quiet_from) ++totals.slow_frames;
        if (t < next_sample) continue;
        sample.t = t;
        const auto st = scheduler.stats();
        write_soak_row(csv, sample, st, action);
        totals.errors = st.errors.size();
        const double rss = static_cast<double>(resident_bytes()) / (1 << 20);
        totals.rss_mb.emplace_back(t, rss);
        if (t >= warm_s) totals.rss_max_after_mb = std::max(totals.rss_max_after_mb, rss);
        sample.frame_ms.clear();
        next_sample += 1;
    }
    std::fclose(csv);
    totals.errors += actions.failures();
    // The level after the warm-up against the level at the end: medians over as long as the warm-up
    // (the budget cycle's troughs and peaks are in both), not single samples.
    const double first = window_median(totals.rss_mb, warm_s, 2 * warm_s);
    const double last = window_median(totals.rss_mb, total_s - warm_s, total_s);
    const double growth = first > 0 ? 100 * (last / first - 1) : 0;
    fmt::print("soak {:.1f} min over {} tiles, budget {} MB, {} render threads: {} frames\n", s.minutes,
               ds.tiles.size(), s.budget >> 20, s.threads, totals.frames);
    fmt::print("resident MB (medians): {:.0f} over the {:.0f} s after the warm-up, {:.0f} over the last {:.0f} s "
               "({:+.1f}%); largest after the warm-up {:.0f}\n",
               first, warm_s, last, warm_s, growth, totals.rss_max_after_mb);
    fmt::print("frames over 100 ms beyond 5 s of the start or a budget change: {}; errors: {}; CSV: {}\n",
               totals.slow_frames, totals.errors, s.csv);
    return growth < 2 && totals.slow_frames == 0 && totals.errors == 0 ? 0 : 1;
}

}  // namespace lidarscout::bench
