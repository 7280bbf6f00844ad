// The viewer's scheduler without a window: time to the first drawable frame (the first chunk
// points), to heightmaps for every patch, and the frame time of the whole-dataset overview at
// 1280 x 720 once they are built. Usage: bench_view [PATH...] (default: the replicated dataset
// /work/bench-data/replica-2025, else ../shared/data/surveys).
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <thread>
#include <vector>

#include "core/thread_pool.hpp"
#include "dataset/dataset.hpp"
#include "viewer/scheduler.hpp"

using namespace lidarscout;
using Clock = std::chrono::steady_clock;

namespace {

double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

std::vector<std::string> default_paths() {
    const std::filesystem::path replica = "/work/bench-data/replica-2025";
    if (std::filesystem::is_directory(replica)) return {replica.string()};
    return {std::string(LIDARSCOUT_DATA_DIR) + "/surveys"};
}

}  // namespace

int main(int argc, char** argv) {
    std::vector<std::string> paths(argv + 1, argv + argc);
    if (paths.empty()) paths = default_paths();
    const auto t0 = Clock::now();
    const auto ds = dataset::open_dataset(paths);
    const double headers = since(t0);
    const auto& b = ds.bounds_m;
    const render::Camera camera = render::Camera::looking_at_bounds(b.min_x, b.min_y, b.min_z, b.max_x, b.max_y,
                                                                    b.max_z, 1280, 720);
    viewer::SchedulerOptions o;
    o.cnn = false, o.full_res = false;
    o.camera = camera;
    viewer::Scheduler scheduler(ds, o);
    ThreadPool pool(std::max(1u, std::thread::hardware_concurrency()));
    double first_frame = -1;
    while (first_frame < 0) {
        const auto snap = scheduler.snapshot();
        if (!snap->chunk_points.empty() || !snap->heightmaps.empty()) {
            viewer::render_snapshot(*snap, camera, viewer::SceneStyle{}, pool);
            first_frame = since(t0);
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    double first_heightmap = -1;
    while (!scheduler.idle()) {
        if (first_heightmap < 0 && scheduler.stats().heightmaps_linear > 0) first_heightmap = since(t0);
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    const double all_heightmaps = since(t0);
    const auto st = scheduler.stats();
    const auto snap = scheduler.snapshot();
    std::vector<double> frames;
    for (int i = 0; i < 5; ++i) {
        const auto f0 = Clock::now();
        viewer::render_snapshot(*snap, camera, viewer::SceneStyle{}, pool);
        frames.push_back(since(f0));
    }
    std::sort(frames.begin(), frames.end());
    fmt::print("{} tiles, {} chunk points, {} patches ({} heightmaps)\n", ds.tiles.size(), st.chunk_points_loaded,
               st.linear.total, st.heightmaps_linear);
    fmt::print("headers {:.3f} s; first frame {:.3f} s; first heightmap {:.3f} s; all heightmaps {:.3f} s; "
               "overview frame 1280x720 {:.1f} ms (median of 5)\n",
               headers, first_frame, first_heightmap, all_heightmaps, 1000 * frames[2]);
    return 0;
}
