// Benchmark: heightmap reconstruction per patch (96 x 96 window), single thread, warm cache.
// Prints ms of thread CPU time per patch (median of 5 runs over the same patches; CPU time so
// that other processes on a shared machine disturb less) for every stage of Algorithm 1
// and for each baseline, on synthetic terrain (~370 chunk points per window, the paper's
// density) and on real points of the eastern Kentucky survey sampled as `eval` does (every
// K-th point, K by the stride rule), at >= 1,000 random patch positions. The heap is kept between
// patches (mallopt), as in a long-running process; one line gives Algorithm 1 with glibc's default
// trimming, where every patch's buffers are fresh pages (page faults are slow in some VMs).
// Usage: bench_recon [PATCHES] [SURVEY_DIR]
//   (default: 1000, ../shared/data/surveys/ky-jmo335-eastern-kentucky)
#include <fmt/format.h>
#include <malloc.h>
#include <time.h>

#include <algorithm>
#include <array>
#include <memory>
#include <cmath>
#include <filesystem>
#include <functional>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "bench_main.hpp"
#include "core/error.hpp"
#include "core/thread_pool.hpp"
#include "dataset/dataset.hpp"
#include "core/patch_grid.hpp"
#include "recon/cubic.hpp"
#include "recon/interpolation.hpp"
#include "recon/methods.hpp"
#include "recon/nearest.hpp"
#include "recon/splat.hpp"
#include "pipelines/survey_samples.hpp"

using namespace lidarscout;
using namespace lidarscout::recon;
using namespace lidarscout::pipelines;

namespace {

// CPU time of this thread in ms: robust to other processes on a shared machine.
double thread_ms() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}

// Median over 5 runs of the mean ms per patch of fn over all patches (after one warm-up).
double ms_per_patch(std::size_t patches, const std::function<void(std::size_t)>& fn) {
    for (std::size_t i = 0; i < patches; ++i) fn(i);
    std::vector<double> runs;
    for (int r = 0; r < 5; ++r) {
        const double t0 = thread_ms();
        for (std::size_t i = 0; i < patches; ++i) fn(i);
        runs.push_back((thread_ms() - t0) / patches);
    }
    std::sort(runs.begin(), runs.end());
    return runs[2];
}

double terrain(double x, double y) {
    return 300.0 + 40.0 * std::sin(x / 150.0) * std::cos(y / 110.0) + 0.05 * x - 0.02 * y +
           5.0 * std::sin(x / 23.0 + y / 31.0);
}

using Window = std::vector<lidarscout::OverviewPoint>;

std::vector<Window> synthetic_windows(std::size_t count, std::size_t points_per_window) {
    std::vector<Window> out;
    std::mt19937_64 rng(2025);
    std::uniform_real_distribution<double> u(0.0, 960.0);
    std::uniform_int_distribution<int> c(0, 255);
    for (std::size_t k = 0; k < count; ++k) {
        std::vector<lidarscout::OverviewPoint> window(points_per_window);
        const double ox = 640.0 * k;  // patches side by side
        for (auto& p : window) {
            p.x = ox + u(rng);
            p.y = u(rng);
            p.z = terrain(p.x, p.y);
            p.rgb = {static_cast<std::uint8_t>(c(rng)), static_cast<std::uint8_t>(c(rng)),
                     static_cast<std::uint8_t>(c(rng))};
        }
        out.push_back(std::move(window));
    }
    return out;
}

double synthetic_patch_min_x(std::size_t k) { return 640.0 * k + 160.0; }

// Real chunk points: the survey sampled as `eval` does (every K-th point, K by the stride rule),
// and patches at random positions (not only on the 640 m lattice, so a small survey gives
// many distinct windows). Gathering = the grid query around the patch + make_patch_points.
struct RealPatches {
    std::unique_ptr<pipelines::SurveySamples> samples;
    std::vector<std::pair<lidarscout::CellKey, std::array<double, 2>>> positions;  // cell, patch min corner
    std::uint64_t stride = 0;
};

PatchPoints gather(const RealPatches& r, std::size_t i) {
    const auto& grid = *r.samples->samples.front().chunk_points;
    const auto& [cell, corner] = r.positions[i];
    const auto points = grid.window(cell, 160.0 + 640.0);  // covers the shifted window
    return make_patch_points(points, corner[0], corner[1]);
}

RealPatches real_patches(const std::filesystem::path& dir, std::size_t count, std::vector<PatchPoints>& out) {
    RealPatches r;
    const auto ds = dataset::open_dataset({dir.string()});
    const Lattice lattice = lattice_for(ds, PatchSpec{});
    r.stride = auto_stride(ds, lattice.spec);
    ThreadPool pool(std::max(1u, std::thread::hardware_concurrency()));
    r.samples = std::make_unique<SurveySamples>(sample_survey(ds, {{lattice, r.stride, {}}}, pool));
    const auto& grid = *r.samples->samples.front().chunk_points;
    const auto cells = grid.cells();
    std::mt19937_64 rng(5);
    for (std::size_t tries = 0; out.size() < count && tries < 20 * count && !cells.empty(); ++tries) {
        const auto cell = cells[rng() % cells.size()];
        const std::array<double, 2> corner{grid.cell_min_x(cell) + (rng() % 640),
                                           grid.cell_min_y(cell) + (rng() % 640)};
        r.positions.emplace_back(cell, corner);
        PatchPoints p = gather(r, r.positions.size() - 1);
        if (p.status == PatchStatus::Ok) {
            out.push_back(std::move(p));
        } else {
            r.positions.pop_back();
        }
    }
    return r;
}

struct Row {
    std::string stage;
    double synthetic = NAN, real = NAN;
};

void run_stages(const std::vector<PatchPoints>& patches, double Row::*column, std::vector<Row>& rows) {
    const std::size_t n = patches.size();
    std::vector<PatchGeometry> geometry(n);
    std::vector<PointValues> heights(n), colours(n);
    for (std::size_t i = 0; i < n; ++i) {
        geometry[i] = build_geometry(patches[i]);
        heights[i] = height_values(patches[i]);
        colours[i] = colour_values(patches[i]);
    }
    const auto put = [&](const std::string& stage, double ms) {
        auto it = std::find_if(rows.begin(), rows.end(), [&](const Row& r) { return r.stage == stage; });
        if (it == rows.end()) it = rows.insert(rows.end(), Row{stage});
        (*it).*column = ms;
    };
    volatile std::size_t sink = 0;
    put("triangulation (CGAL)",
        ms_per_patch(n, [&](std::size_t i) { sink = sink + triangulate(patches[i]).triangles.size(); }));
    put("face map", ms_per_patch(n, [&](std::size_t i) {
            sink = sink + build_face_map(geometry[i].triangulation, 96).face.size();
        }));
    put("nearest map", ms_per_patch(n, [&](std::size_t i) {
            sink = sink + nearest_point_map(std::span<const GridXY>(geometry[i].triangulation.vertices.data(),
                                                                   geometry[i].triangulation.real_count), 96).size();
        }));
    put("NN + linear images (h, RGB)", ms_per_patch(n, [&](std::size_t i) {
            sink = sink + nearest_image(geometry[i], heights[i]).values.size() +
                   linear_image(geometry[i], heights[i]).values.size() +
                   nearest_image(geometry[i], colours[i]).values.size() +
                   linear_image(geometry[i], colours[i]).values.size();
        }));
    put("= Algorithm 1 (interpolate_patch)", ms_per_patch(n, [&](std::size_t i) {
            sink = sink + interpolate_patch(patches[i]).height_linear.values.size();
        }));
    for (const Method m : kAllMethods) {
        put(fmt::format("baseline {} (h, RGB, all steps)", method_name(m)), ms_per_patch(n, [&](std::size_t i) {
                sink = sink + reconstruct(patches[i], m).height.values.size();
            }));
    }
}

double row_value(const std::vector<Row>& rows, const std::string& stage, double Row::*column) {
    for (const auto& r : rows) {
        if (r.stage == stage) return r.*column;
    }
    return NAN;
}

double median_points(const std::vector<PatchPoints>& patches) {
    std::vector<std::size_t> n;
    for (const auto& p : patches) n.push_back(p.points.size());
    if (n.empty()) return NAN;
    std::sort(n.begin(), n.end());
    return static_cast<double>(n[n.size() / 2]);
}

}  // namespace

constexpr const char* kUsage =
    "[PATCHES] [SURVEY_DIR]   (default: 1000, ../shared/data/surveys/ky-jmo335-eastern-kentucky)";

int main(int argc, char** argv) {
    return lidarscout::bench::bench_main("bench_recon", kUsage, argc, argv, [](int argc, char** argv) {
        const std::size_t count = argc > 1 ? std::stoul(argv[1]) : 1000;
        const std::filesystem::path survey =
            argc > 2 ? std::filesystem::path(argv[2])
                     : std::filesystem::path(LIDARSCOUT_DATA_DIR) / "surveys" / "ky-jmo335-eastern-kentucky";
        std::vector<Row> rows;
        const auto windows = synthetic_windows(count, 370);
        std::vector<PatchPoints> synthetic;
        for (std::size_t k = 0; k < windows.size(); ++k) {
            synthetic.push_back(make_patch_points(windows[k], synthetic_patch_min_x(k), 160.0));
        }
        // First with glibc's default heap trimming: every patch's ~0.5 MB of buffers are fresh
        // pages (page faults). Then with the heap kept, as in a long-running process.
        const double fresh =
            ms_per_patch(synthetic.size(), [&](std::size_t i) { (void)interpolate_patch(synthetic[i]); });
        mallopt(M_TRIM_THRESHOLD, 256 << 20);
        mallopt(M_MMAP_THRESHOLD, 64 << 20);
        rows.push_back({"gathering (real: grid query; patch points)", ms_per_patch(windows.size(), [&](std::size_t k) {
                            (void)make_patch_points(windows[k], synthetic_patch_min_x(k), 160.0);
                        })});
        run_stages(synthetic, &Row::synthetic, rows);
        std::vector<PatchPoints> real;
        RealPatches positions;
        if (std::filesystem::is_directory(survey)) positions = real_patches(survey, count, real);
        if (!real.empty()) {
            run_stages(real, &Row::real, rows);
            rows.front().real = ms_per_patch(real.size(), [&](std::size_t i) { (void)gather(positions, i); });
            rows.push_back(
                {"= gathering + Algorithm 1",
                 rows.front().synthetic + row_value(rows, "= Algorithm 1 (interpolate_patch)", &Row::synthetic),
                 ms_per_patch(real.size(), [&](std::size_t i) { (void)interpolate_patch(gather(positions, i)); })});
        }

        fmt::print("bench_recon: ms per patch, single thread, 96 x 96 texels, median of 5 runs\n");
        fmt::print("  synthetic: {} patches, {:.0f} chunk points per window (median)\n", synthetic.size(),
                   median_points(synthetic));
        fmt::print(
            "  real: {}, every {}th point (stride rule), {} patches at random positions, {:.0f} points per window "
            "(median)\n",
            real.empty() ? "not found" : survey.filename().string(), positions.stride, real.size(),
            median_points(real));
        fmt::print("  thread CPU time; heap kept between patches (mallopt); Algorithm 1 with glibc's default\n"
                   "  trimming instead (fresh pages every patch): {:.4f} ms (synthetic)\n", fresh);
        fmt::print("{:<38} {:>10} {:>10}\n", "stage", "synthetic", "real");
        for (const Row& r : rows) fmt::print("{:<38} {:>10.4f} {:>10.4f}\n", r.stage, r.synthetic, r.real);
        return 0;
    });
}
