// Benchmark: the CPU software rasterizer at 1280 x 720 (wall-clock medians of --runs runs,
// default 5, after one warm-up):
//   - the point pass: 20 M points (20 batches of 1 M, one per 1 km tile, terrain-like) seen
//     whole by the overview camera, on 1 thread and on all threads, in points per second;
//   - the heightmap pass: 2,000 patches of 64 x 64 texels (a 50 x 40 grid of 640 m patches)
//     under the overview camera, with the LOD the pass picks, on 1 thread and all threads, and
//     without the outline fill (its cost);
//   - the resolve pass, with and without eye-dome lighting, and the framebuffer clear;
//   - with --frames: whole frames as the viewer draws them (draw_frame: clear, pass, resolve with
//     EDL, the image back in host memory) of the points and of the patches, on the CPU and, when
//     its plugin and a GPU are there, the CUDA backend: points and patches uploaded with every
//     frame (no cache key), and kept on the GPU (with keys: the first frame uploads them, the
//     median frame does not).
// Usage: bench_raster [--runs N] [--points MILLIONS] [--patches N] [--threads N] [--png PREFIX] [--frames]
//   --png writes PREFIX_points.png and PREFIX_heightmaps.png (EDL on) to look at.
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <random>
#include <span>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "bench_main.hpp"
#include "core/error.hpp"
#include "core/thread_pool.hpp"
#include "render/backend.hpp"
#include "render/camera.hpp"
#include "render/framebuffer.hpp"
#include "render/heightmap_pass.hpp"
#include "render/png_writer.hpp"
#include "render/point_pass.hpp"
#include "render/resolve.hpp"

using namespace lidarscout;
using namespace lidarscout::render;

namespace {

constexpr int kWidth = 1280, kHeight = 720;
constexpr double kX0 = 600'000.0, kY0 = 5'200'000.0;  // a UTM-sized origin

struct Options {
    int runs = 5;
    double points_millions = 20;
    int patches = 2000;
    unsigned threads = std::max(1u, std::thread::hardware_concurrency());
    std::string png;
    bool frames = false;
};

Options parse_options(int argc, char** argv) {
    Options o;
    for (int i = 1; i < argc; ++i) {
        const std::string_view arg = argv[i];
        if (arg == "--frames") {
            o.frames = true;
            continue;
        }
        const char* value = i + 1 < argc ? argv[i + 1] : nullptr;
        if (!value) throw Error("bench_raster: " + std::string(arg) + " needs a value");
        if (arg == "--runs") {
            o.runs = std::max(1, std::atoi(value));
        } else if (arg == "--points") {
            o.points_millions = std::max(0.001, std::atof(value));
        } else if (arg == "--patches") {
            o.patches = std::max(1, std::atoi(value));
        } else if (arg == "--threads") {
            o.threads = static_cast<unsigned>(std::max(1, std::atoi(value)));
        } else if (arg == "--png") {
            o.png = value;
        } else {
            throw Error("bench_raster: unknown option " + std::string(arg) +
                        " (known: --runs --points --patches --threads --png --frames)");
        }
        ++i;
    }
    return o;
}

double terrain(double x, double y) {
    return 300.0 + 120.0 * std::sin(x / 2100.0) * std::cos(y / 1700.0) + 35.0 * std::sin(x / 530.0 + y / 410.0) +
           6.0 * std::sin(x / 61.0) * std::cos(y / 47.0);
}

// Median wall-clock seconds of fn over `runs` runs, after one warm-up run.
double median_seconds(int runs, const std::function<void()>& fn) {
    fn();
    std::vector<double> times;
    for (int r = 0; r < runs; ++r) {
        const auto t0 = std::chrono::steady_clock::now();
        fn();
        times.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
    std::sort(times.begin(), times.end());
    return times[times.size() / 2];
}

// Points on 1 km tiles in a grid of `tiles_x` columns, each tile a batch with its own origin.
struct PointSet {
    std::vector<std::vector<PointAttr>> storage;
    std::vector<PointBatch> batches;
};

PointSet make_points(std::size_t total, int tiles) {
    PointSet set;
    const int tiles_x = static_cast<int>(std::ceil(std::sqrt(tiles * 1.25)));
    std::mt19937 rng(42);
    std::uniform_real_distribution<float> u(0.0f, 1000.0f), noise(-0.5f, 0.5f);
    for (int t = 0; t < tiles; ++t) {
        const double ox = kX0 + 1000.0 * (t % tiles_x), oy = kY0 + 1000.0 * (t / tiles_x), oz = 300.0;
        std::vector<PointAttr>& points = set.storage.emplace_back(total / tiles);
        for (PointAttr& p : points) {
            p.dx = u(rng);
            p.dy = u(rng);
            p.dz = static_cast<float>(terrain(ox + p.dx, oy + p.dy) - oz) + noise(rng);
            const auto shade = static_cast<std::uint8_t>(std::clamp(128.0f + p.dz, 0.0f, 255.0f));
            p.r = shade, p.g = static_cast<std::uint8_t>(200 - shade / 2), p.b = 90;
            p.classification = 2;
            p.intensity = static_cast<std::uint16_t>(rng());
        }
        set.batches.push_back({ox, oy, oz, points});
    }
    return set;
}

struct PatchSet {
    std::vector<std::vector<float>> heights;
    std::vector<std::vector<std::uint32_t>> colours;
    std::vector<HeightmapPatch> patches;
};

PatchSet make_patches(int count) {
    PatchSet set;
    const int columns = static_cast<int>(std::ceil(std::sqrt(count * 1.25)));
    for (int k = 0; k < count; ++k) {
        const double ox = kX0 + 640.0 * (k % columns), oy = kY0 + 640.0 * (k / columns);
        std::vector<float>& h = set.heights.emplace_back(64 * 64);
        std::vector<std::uint32_t>& c = set.colours.emplace_back(64 * 64);
        for (int j = 0; j < 64; ++j) {
            for (int i = 0; i < 64; ++i) {
                const double z = terrain(ox + 10.0 * (i + 0.5), oy + 10.0 * (j + 0.5));
                h[j * 64 + i] = static_cast<float>(z);
                const auto g = static_cast<std::uint8_t>(std::clamp(z - 150.0, 0.0, 255.0));
                c[j * 64 + i] = pack_rgba(static_cast<std::uint8_t>(90 + g / 3), g, 70);
            }
        }
        set.patches.push_back({ox, oy, 10.0, 64, h, c});
    }
    return set;
}

Camera overview_of_points(const PointSet& set) {
    double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300};
    for (const PointBatch& b : set.batches) {
        lo[0] = std::min(lo[0], b.origin_x), hi[0] = std::max(hi[0], b.origin_x + 1000.0);
        lo[1] = std::min(lo[1], b.origin_y), hi[1] = std::max(hi[1], b.origin_y + 1000.0);
    }
    return Camera::looking_at_bounds(lo[0], lo[1], 100.0, hi[0], hi[1], 500.0, kWidth, kHeight);
}

Camera overview_of_patches(const PatchSet& set) {
    double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300};
    for (const HeightmapPatch& p : set.patches) {
        lo[0] = std::min(lo[0], p.origin_x), hi[0] = std::max(hi[0], p.origin_x + 640.0);
        lo[1] = std::min(lo[1], p.origin_y), hi[1] = std::max(hi[1], p.origin_y + 640.0);
    }
    return Camera::looking_at_bounds(lo[0], lo[1], 100.0, hi[0], hi[1], 500.0, kWidth, kHeight);
}

std::size_t drawn_pixels(const Framebuffer& fb) {
    return static_cast<std::size_t>(
        std::count_if(fb.data(), fb.data() + static_cast<std::size_t>(fb.width()) * fb.height(),
                      [](std::uint64_t v) { return v != kEmpty; }));
}

void bench_points(const Options& o, ThreadPool& single, ThreadPool& all) {
    const PointSet set = make_points(static_cast<std::size_t>(o.points_millions * 1e6), 20);
    std::size_t total = 0;
    for (const PointBatch& b : set.batches) total += b.points.size();
    const Camera camera = overview_of_points(set);
    Framebuffer fb(kWidth, kHeight);
    const PointPassSettings settings;
    for (ThreadPool* pool : {&single, &all}) {
        const double s = median_seconds(o.runs, [&] {
            fb.clear();
            draw_points(fb, camera, set.batches, settings, *pool);
        });
        fmt::print("point pass       {:>2} thread(s): {:7.1f} ms for {:.1f} M points = {:6.1f} M points/s "
                   "({} px drawn)\n",
                   pool->size(), s * 1e3, total / 1e6, total / s / 1e6, drawn_pixels(fb));
    }
    if (!o.png.empty()) {
        ResolveSettings rs;
        rs.edl_strength = 1.0f;
        write_png(o.png + "_points.png", resolve(fb, rs, all));
    }
}

void bench_resolve(const Options& o, const Framebuffer& fb, ThreadPool& all) {
    ResolveSettings plain, edl;
    edl.edl_strength = 1.0f;
    const double s_plain = median_seconds(o.runs, [&] { resolve(fb, plain, all); });
    const double s_edl = median_seconds(o.runs, [&] { resolve(fb, edl, all); });
    Framebuffer scratch(kWidth, kHeight);
    const double s_clear = median_seconds(o.runs, [&] { scratch.clear(); });
    fmt::print("resolve          {:>2} thread(s): {:7.2f} ms plain, {:.2f} ms with EDL; clear {:.2f} ms\n", all.size(),
               s_plain * 1e3, s_edl * 1e3, s_clear * 1e3);
    if (!o.png.empty()) write_png(o.png + "_heightmaps.png", resolve(fb, edl, all));
}

void bench_heightmaps(const Options& o, ThreadPool& single, ThreadPool& all) {
    const PatchSet set = make_patches(o.patches);
    const Camera camera = overview_of_patches(set);
    Framebuffer fb(kWidth, kHeight);
    const HeightmapPassSettings settings;
    std::vector<int> steps;
    for (const HeightmapPatch& p : set.patches) {
        const auto [lo, hi] = std::minmax_element(p.heights.begin(), p.heights.end());
        steps.push_back(lod_step(p, *lo, *hi, camera, settings.lod_quad_px));
    }
    std::sort(steps.begin(), steps.end());
    for (ThreadPool* pool : {&single, &all}) {
        const double s = median_seconds(o.runs, [&] {
            fb.clear();
            draw_heightmaps(fb, camera, set.patches, settings, *pool);
        });
        fmt::print("heightmap pass   {:>2} thread(s): {:7.1f} ms for {} patches of 64x64 (LOD step {}..{}, median {}; "
                   "{} px drawn)\n",
                   pool->size(), s * 1e3, set.patches.size(), steps.front(), steps.back(), steps[steps.size() / 2],
                   drawn_pixels(fb));
    }
    HeightmapPassSettings no_outline = settings;
    no_outline.fill_outline = false;
    const double without = median_seconds(o.runs, [&] {
        fb.clear();
        draw_heightmaps(fb, camera, set.patches, no_outline, all);
    });
    fmt::print("heightmap pass   {:>2} thread(s): {:7.1f} ms without the outline fill ({} px drawn)\n", all.size(),
               without * 1e3, drawn_pixels(fb));
    HeightmapPassSettings full = settings;
    full.fixed_step = 1;
    const double s = median_seconds(o.runs, [&] {
        fb.clear();
        draw_heightmaps(fb, camera, set.patches, full, all);
    });
    fmt::print("heightmap pass   {:>2} thread(s): {:7.1f} ms at full detail (step 1, {:.1f} M triangles)\n", all.size(),
               s * 1e3, set.patches.size() * 64 * 64 * 2 / 1e6);
    fb.clear();
    draw_heightmaps(fb, camera, set.patches, settings, all);
    bench_resolve(o, fb, all);
}

// Whole frames of one scene on each backend that is available here (the CUDA one with the
// points' keys given, `keyed`, or not).
void bench_frame(const Options& o, const std::string& what, const Camera& camera,
                 std::span<const HeightmapPatch> patches, std::span<const PointLayer> layers, ThreadPool& all,
                 bool keyed = false) {
    FrameSettings settings;
    settings.resolve.edl_strength = 1.0f;
    for (const Backend backend : {Backend::Cpu, Backend::Cuda}) {
        if (keyed && backend == Backend::Cpu) continue;  // the CPU ignores the keys
        if (backend == Backend::Cuda && !cuda_unavailable_reason().empty()) {
            fmt::print("frame of {:<26} cuda: unavailable ({})\n", what, cuda_unavailable_reason());
            continue;
        }
        std::size_t drawn = 0;
        const auto frame = [&] { drawn = draw_frame(backend, camera, patches, layers, settings, all).drawn_pixels; };
        const auto t0 = std::chrono::steady_clock::now();
        frame();
        const double first = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        const double s = median_seconds(o.runs, frame);
        fmt::print("frame of {:<26} {:<4} {:7.2f} ms, first {:7.2f} ms ({} px drawn){}\n", what,
                   backend_name(backend), s * 1e3, first * 1e3, drawn,
                   backend == Backend::Cuda ? " on " + cuda_device_name() : fmt::format(", {} threads", all.size()));
    }
}

void bench_frames(const Options& o, ThreadPool& all) {
    const PointSet points = make_points(static_cast<std::size_t>(o.points_millions * 1e6), 20);
    {
        const std::string name = fmt::format("{:.0f} M points", o.points_millions);
        const PointLayer layer{points.batches, 1};
        bench_frame(o, name, overview_of_points(points), {}, std::span<const PointLayer>(&layer, 1), all);
        std::vector<PointBatch> keyed = points.batches;
        for (PointBatch& b : keyed) b.cache_key = new_cache_key();
        const PointLayer kept{keyed, 1};
        bench_frame(o, name + " (kept on GPU)", overview_of_points(points), {}, std::span<const PointLayer>(&kept, 1),
                    all, true);
    }
    const PatchSet patches = make_patches(o.patches);
    const std::string name = fmt::format("{} patches", o.patches);
    bench_frame(o, name, overview_of_patches(patches), patches.patches, {}, all);
    std::vector<HeightmapPatch> keyed = patches.patches;
    for (HeightmapPatch& p : keyed) p.cache_key = new_cache_key();
    bench_frame(o, name + " (kept on GPU)", overview_of_patches(patches), keyed, {}, all, true);
}

}  // namespace

constexpr const char* kUsage =
    "[--runs N] [--points MILLIONS] [--patches N] [--threads N] [--png PREFIX] [--frames]";

int main(int argc, char** argv) {
    return lidarscout::bench::bench_main("bench_raster", kUsage, argc, argv, [](int argc, char** argv) {
        const Options o = parse_options(argc, argv);
        ThreadPool single(1), all(o.threads);
        fmt::print("bench_raster: {}x{}, median of {} runs, {} hardware threads\n", kWidth, kHeight, o.runs,
                   std::thread::hardware_concurrency());
        bench_points(o, single, all);
        bench_heightmaps(o, single, all);
        if (o.frames) bench_frames(o, all);
        return 0;
    });
}
