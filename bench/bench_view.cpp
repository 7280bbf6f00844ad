// The viewer's scheduler and renderer without a window.
//
// Default mode: time to the first drawable frame (the first chunk points), to heightmaps for
// every patch (linear, and with --cnn the network's too), and the frame time of the
// whole-dataset overview at 1280 x 720 once they are built.
//
// --flight SECONDS: the scripted flight of viewer/flight_path.hpp (from high above the whole
// dataset down to 200 m over its diagonal) with full-resolution streaming on, drawing frames
// back to back at 1280 x 720 as the viewer does while the scheduler loads. Prints frame times
// (median, 95th percentile, worst), the longest wait for the scheduler (taking the camera and
// the snapshot: what loading could stall), frames over 100 ms, and memory against the budget.
//
// Usage: bench_view [PATH...] [--cnn] [--flight SECONDS] [--memory MB] [--threads N] [--backend cpu|cuda|auto]
// (default PATH: the replicated dataset /work/bench-data/replica-2025, else
// ../shared/data/surveys).
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "core/process_memory.hpp"
#include "core/thread_pool.hpp"
#include "dataset/dataset.hpp"
#include "viewer/flight_path.hpp"
#include "viewer/scheduler.hpp"

using namespace lidarscout;
using Clock = std::chrono::steady_clock;

namespace {

double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

struct Options {
    std::vector<std::string> paths;
    bool cnn = false;
    double flight_s = 0;           // 0: the loading benchmark
    std::uint64_t memory_mb = 1024;
    unsigned threads = 0;          // render threads (0: all cores)
    viewer::SceneStyle style;      // its backend from --backend
};

Options parse(int argc, char** argv) {
    Options o;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        const auto value = [&] {
            if (i + 1 >= argc) throw std::invalid_argument(a + " needs a value");
            return std::string(argv[++i]);
        };
        if (a == "--cnn") o.cnn = true;
        else if (a == "--flight") o.flight_s = std::stod(value());
        else if (a == "--memory") o.memory_mb = std::stoull(value());
        else if (a == "--threads") o.threads = static_cast<unsigned>(std::stoul(value()));
        else if (a == "--backend") o.style.backend = render::choose_backend(render::parse_backend(value())).backend;
        else if (a.starts_with("--")) throw std::invalid_argument("unknown option " + a);
        else o.paths.push_back(a);
    }
    if (o.paths.empty()) {
        const std::filesystem::path replica = "/work/bench-data/replica-2025";
        o.paths = {std::filesystem::is_directory(replica) ? replica.string()
                                                           : std::string(LIDARSCOUT_DATA_DIR) + "/surveys"};
    }
    return o;
}

double percentile(std::vector<double> v, double q) {
    if (v.empty()) return 0;
    std::sort(v.begin(), v.end());
    return v[std::min(v.size() - 1, static_cast<std::size_t>(q * static_cast<double>(v.size() - 1) + 0.5))];
}

unsigned pool_threads(const Options& o) { return o.threads ? o.threads : std::max(1u, std::thread::hardware_concurrency()); }

int loading(const Options& o, const dataset::Dataset& ds, double headers) {
    const auto t0 = Clock::now();
    const auto& b = ds.bounds_m;
    const render::Camera camera = render::Camera::looking_at_bounds(b.min_x, b.min_y, b.min_z, b.max_x, b.max_y,
                                                                    b.max_z, 1280, 720);
    viewer::SchedulerOptions so;
    so.cnn = o.cnn, so.full_res = false;
    so.camera = camera;
    viewer::Scheduler scheduler(ds, so);
    ThreadPool pool(pool_threads(o));
    double first_frame = -1;
    while (first_frame < 0) {
        const auto snap = scheduler.snapshot();
        if (!snap->chunk_points.empty() || !snap->heightmaps.empty()) {
            viewer::render_snapshot(*snap, camera, o.style, pool);
            first_frame = since(t0);
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    double first_heightmap = -1, all_linear = -1;
    while (!scheduler.idle()) {
        const auto st = scheduler.stats();
        if (first_heightmap < 0 && st.heightmaps_linear + st.heightmaps_cnn > 0) first_heightmap = since(t0);
        if (all_linear < 0 && st.linear.total > 0 && st.tiles_loaded.done == st.tiles_loaded.total &&
            st.linear.done == st.linear.total)
            all_linear = since(t0);
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    const double all_done = since(t0);
    if (all_linear < 0) all_linear = all_done;
    const auto st = scheduler.stats();
    const auto snap = scheduler.snapshot();
    std::vector<double> frames;
    for (int i = 0; i < 5; ++i) {
        const auto f0 = Clock::now();
        viewer::render_snapshot(*snap, camera, o.style, pool);
        frames.push_back(since(f0));
    }
    fmt::print("{} tiles, {} chunk points, {} patches ({} linear heightmaps, {} CNN heightmaps)\n", ds.tiles.size(),
               st.chunk_points_loaded, st.linear.total, st.heightmaps_linear, st.heightmaps_cnn);
    for (const auto& n : st.notes) fmt::print("note: {}\n", n);
    fmt::print("headers {:.3f} s; first frame {:.3f} s; first heightmap {:.3f} s; all linear heightmaps {:.3f} s",
               headers, first_frame, first_heightmap, all_linear);
    if (o.cnn) fmt::print("; all CNN heightmaps {:.3f} s", all_done);
    fmt::print("; overview frame 1280x720 {:.1f} ms (median of 5)\n", 1000 * percentile(frames, 0.5));
    return 0;
}

int flight(const Options& o, const dataset::Dataset& ds) {
    viewer::FlightPath path;
    viewer::SchedulerOptions so;
    so.cnn = o.cnn;
    so.memory_budget = o.memory_mb << 20;
    so.camera = viewer::flight_camera(ds.bounds_m, 0, path);
    const std::uint64_t rss0 = resident_bytes();
    viewer::Scheduler scheduler(ds, so);
    ThreadPool pool(pool_threads(o));
    std::vector<double> frame_ms, camera_ms, snapshot_ms;
    std::vector<std::string> slow;  // frames over 100 ms: when, and how long
    std::uint64_t peak_rss = rss0;
    const auto start = Clock::now();
    for (double t = 0; t < 1.0; t = since(start) / o.flight_s) {
        const auto f0 = Clock::now();
        const render::Camera camera = viewer::flight_camera(ds.bounds_m, t, path);
        scheduler.set_camera(camera);
        camera_ms.push_back(1000 * since(f0));
        const auto s0 = Clock::now();
        const auto snap = scheduler.snapshot();
        snapshot_ms.push_back(1000 * since(s0));
        viewer::render_snapshot(*snap, camera, o.style, pool);
        frame_ms.push_back(1000 * since(f0));
        if (frame_ms.back() > 100) slow.push_back(fmt::format("{:.0f} ms at {:.2f} s", frame_ms.back(), since(start)));
        peak_rss = std::max(peak_rss, resident_bytes());
    }
    const auto st = scheduler.stats();
    const auto over = [](const std::vector<double>& v) { return std::count_if(v.begin(), v.end(), [](double x) { return x > 100; }); };
    fmt::print("flight {:.0f} s over {} tiles at 1280x720, CNN {}, budget {} MB: {} frames\n", o.flight_s,
               ds.tiles.size(), o.cnn ? "on" : "off", o.memory_mb, frame_ms.size());
    fmt::print("frame ms: median {:.1f}, p95 {:.1f}, worst {:.1f}; frames over 100 ms: {}\n", percentile(frame_ms, 0.5),
               percentile(frame_ms, 0.95), percentile(frame_ms, 1.0), over(frame_ms));
    if (!slow.empty()) fmt::print("frames over 100 ms: {}\n", fmt::join(slow, ", "));
    fmt::print("waiting for the scheduler, ms: set_camera median {:.3f}, worst {:.3f}; snapshot median {:.3f}, "
               "worst {:.3f}; waits over 100 ms: {}\n",
               percentile(camera_ms, 0.5), percentile(camera_ms, 1.0), percentile(snapshot_ms, 0.5),
               percentile(snapshot_ms, 1.0), over(camera_ms) + over(snapshot_ms));
    fmt::print("memory: peak RSS {} MB ({} MB before the scheduler), scheduler peak {} MB of {} MB\n", peak_rss >> 20,
               rss0 >> 20, st.peak_bytes_used >> 20, st.memory_budget >> 20);
    fmt::print("at the end: {} of {} tiles' chunk points, {} linear + {} CNN heightmaps, {} full-res tiles resident "
               "({} points), {} released\n",
               st.tiles_loaded.done, st.tiles_loaded.total, st.heightmaps_linear, st.heightmaps_cnn, st.full_res_tiles,
               st.full_res_points, st.full_res_released);
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    try {
        const Options o = parse(argc, argv);
        const auto t0 = Clock::now();
        const auto ds = dataset::open_dataset(o.paths);
        const double headers = since(t0);
        return o.flight_s > 0 ? flight(o, ds) : loading(o, ds, headers);
    } catch (const std::exception& e) {
        fmt::print(stderr, "bench_view: {}\n", e.what());
        return 1;
    }
}
