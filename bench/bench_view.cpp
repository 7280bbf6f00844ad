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
// the snapshot: what loading could stall), frames over 100 ms, and memory against the budget, with
// the resident size before the scheduler and the bytes the dataset's metadata holds per tile
// (dataset/metadata.hpp). --classes, --returns and --intensity draw only the points they keep
// (what the viewer's Filters section does), to measure what a filter costs a frame.
//
// --converge: how fast the picture converges to the real points. Three fixed cameras (the whole
// dataset from above; a medium view about 2 km wide, or the dataset's width when smaller, looking
// down 60 degrees; a close view 300 m wide looking down 45 degrees; --camera NAME, repeatable, runs
// only those), each with a freshly opened scheduler drawing frames as the viewer does, at most 60 a
// second (vsync), through viewer/frame_refiner.hpp (a still frame is refined once with every point
// held); the PSNR (dB, eye-dome lighting off) of the live frame against a reference frame at 0.5, 1,
// 2, 5, 10 and 30 s. The reference, made before the live run (its memory returned first): when the
// visible tiles' points fit in half the default budget, a second scheduler with that budget, idle,
// every visible tile at full resolution, drawn with every point ("all points"); else (a country seen
// whole) every point of the visible tiles streamed into the frame as it is decoded, over the linear
// heightmaps, never all held (viewer/reference_frame.hpp; "all points, streamed"): minutes for
// billions of points, with progress on stderr, cached in --reference-cache DIR (default
// /tmp/lidarscout-references) by dataset, camera, image size and style, so built once.
// Memory: the peak resident size of the live runs, and at that peak what the scheduler counted
// against the budget and the C heap's bytes in use and freed but kept; loads and releases.
// --png DIR writes each sampled frame, each of its layers alone and the reference as PNGs.
// --json prints {"dataset", "cameras": [{"name", "reference", "samples": [{"t", "psnr_db"}], "never_worse",
// "loads", "releases", "at_peak_rss": {"rss_mb", "counted_mb", "heap_in_use_mb", "heap_free_kept_mb"}}],
// "peak_rss_mb", "budget_mb", "scheduler_peak_mb", "rss_before_mb"}.
//
// --load-cost: for each camera of --converge, a freshly opened scheduler (nothing drawn) until it
// is idle: the wall time and the CPU seconds it took (the CPU seconds hold on a loaded machine,
// where wall times do not), median of --runs runs (default 3).
//
// --scaling (with --flight): the flight over each PATH in turn, each opened alone (e.g. virtual
// replicas of 2,025, 19,600 and 152,100 tiles), printed as one table: frame times, the first
// PATH's median as the reference of the ratios, waits for the scheduler, RSS before the
// scheduler and at its peak, and what had come by the end (tiles' chunk points, heightmaps).
//
// --soak MINUTES [--soak-csv FILE] [--soak-action-every SECONDS]: the soak of bench/view_soak.hpp, a
// tour with the user's actions (filters, colour modes, profiles, area measures, budget changes) for
// MINUTES, resident size and frame times every second to the CSV (default soak.csv); exit 1 when the
// resident size grew 2% or more after the warm-up, a frame took over 100 ms or an error came.
//
// Usage: bench_view [PATH...] [--cnn] [--flight SECONDS [--scaling]]
//                   [--converge [--json] [--png DIR] [--camera NAME]... [--reference-cache DIR]]
//                   [--load-cost [--runs N]]
//                   [--soak MINUTES [--soak-csv FILE] [--soak-action-every SECONDS]]
//                   [--lod-spacing PX]
//                   [--memory MB] [--threads N] [--backend cpu|cuda|auto]
// (default PATH: the replicated dataset /work/bench-data/replica-2025, else
// ../shared/data/surveys).
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <sys/resource.h>

#include <chrono>
#include <cmath>
#include <numbers>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "bench_main.hpp"
#include "core/process_memory.hpp"
#include "core/thread_pool.hpp"
#include "dataset/dataset.hpp"
#include "dataset/metadata.hpp"
#include "render/image_compare.hpp"
#include "render/png_writer.hpp"
#include "view_soak.hpp"
#include "viewer/flight_path.hpp"
#include "viewer/frame_refiner.hpp"
#include "viewer/reference_frame.hpp"
#include "viewer/scheduler.hpp"
#include "viewer/visibility.hpp"

using namespace lidarscout;
using Clock = std::chrono::steady_clock;

namespace {

constexpr auto kVsync = std::chrono::microseconds(16'667);

double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

struct Options {
    std::vector<std::string> paths;
    bool cnn = false;
    double flight_s = 0;           // 0: the loading benchmark
    double soak_minutes = 0;       // --soak
    std::string soak_csv = "soak.csv";
    double soak_action_every_s = 15;
    bool converge = false, json = false, load_cost = false;
    bool scaling = false;          // --scaling: the flight over each PATH in turn, one table
    int runs = 3;                  // --load-cost
    std::string png_dir;           // --converge: write every sampled frame and reference here
    std::vector<std::string> cameras;  // --camera NAME (repeatable): the converge cameras to run (empty: all)
    std::string reference_cache = "/tmp/lidarscout-references";  // --reference-cache: streamed references
    std::uint64_t memory_mb = 1024;
    unsigned threads = 0;          // render threads (0: all cores)
    viewer::SceneStyle style;      // its backend from --backend, its filter from --classes/--returns/--intensity
};

Options parse(int argc, char** argv) {
    Options o;
    std::string classes, returns, intensity;  // the filter's options
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        const auto value = [&] {
            if (i + 1 >= argc) throw std::invalid_argument(a + " needs a value");
            return std::string(argv[++i]);
        };
        if (a == "--cnn") o.cnn = true;
        else if (a == "--flight") o.flight_s = std::stod(value());
        else if (a == "--converge") o.converge = true;
        else if (a == "--soak") o.soak_minutes = std::stod(value());
        else if (a == "--soak-csv") o.soak_csv = value();
        else if (a == "--soak-action-every") o.soak_action_every_s = std::stod(value());
        else if (a == "--scaling") o.scaling = true;
        else if (a == "--json") o.json = true;
        else if (a == "--load-cost") o.load_cost = true;
        else if (a == "--runs") o.runs = std::stoi(value());
        else if (a == "--png") o.png_dir = value();
        else if (a == "--camera") o.cameras.push_back(value());
        else if (a == "--reference-cache") o.reference_cache = value();
        else if (a == "--lod-spacing") o.style.lod_spacing_px = std::stod(value());
        else if (a == "--memory") o.memory_mb = std::stoull(value());
        else if (a == "--threads") o.threads = static_cast<unsigned>(std::stoul(value()));
        else if (a == "--backend") o.style.backend = render::choose_backend(render::parse_backend(value())).backend;
        else if (a == "--classes") classes = value();
        else if (a == "--returns") returns = value();
        else if (a == "--intensity") intensity = value();
        else if (a.starts_with("--")) throw std::invalid_argument("unknown option " + a);
        else o.paths.push_back(a);
    }
    o.style.filter = PointFilter::parse(classes, returns, intensity);
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

unsigned pool_threads(const Options& o) {
    return o.threads ? o.threads : std::max(1u, std::thread::hardware_concurrency());
}

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

// One flight's figures (see --flight).
struct FlightResult {
    std::size_t tiles = 0;
    std::vector<double> frame_ms, camera_ms, snapshot_ms;
    std::vector<std::string> slow;  // frames over 100 ms: when, and how long
    std::uint64_t rss_before = 0, peak_rss = 0;
    viewer::SchedulerStats stats;   // at the end
};

std::size_t over_100ms(const std::vector<double>& v) {
    return static_cast<std::size_t>(std::count_if(v.begin(), v.end(), [](double x) { return x > 100; }));
}

FlightResult fly(const Options& o, const dataset::Dataset& ds) {
    viewer::FlightPath path;
    viewer::SchedulerOptions so;
    so.cnn = o.cnn;
    so.memory_budget = o.memory_mb << 20;
    so.camera = viewer::flight_camera(ds.bounds_m, 0, path);
    FlightResult r;
    r.tiles = ds.tiles.size();
    r.rss_before = r.peak_rss = resident_bytes();
    viewer::Scheduler scheduler(ds, so);
    viewer::FrameRefiner refiner;
    ThreadPool pool(pool_threads(o));
    const auto start = Clock::now();
    for (double t = 0; t < 1.0; t = since(start) / o.flight_s) {
        const auto f0 = Clock::now();
        const render::Camera camera = viewer::flight_camera(ds.bounds_m, t, path);
        scheduler.set_camera(camera);
        r.camera_ms.push_back(1000 * since(f0));
        const auto s0 = Clock::now();
        const auto snap = scheduler.snapshot();
        r.snapshot_ms.push_back(1000 * since(s0));
        refiner.draw(*snap, camera, o.style, pool);
        r.frame_ms.push_back(1000 * since(f0));
        if (r.frame_ms.back() > 100)
            r.slow.push_back(fmt::format("{:.0f} ms at {:.2f} s", r.frame_ms.back(), since(start)));
        r.peak_rss = std::max(r.peak_rss, resident_bytes());
    }
    r.stats = scheduler.stats();
    return r;
}

int flight(const Options& o, const dataset::Dataset& ds) {
    const FlightResult r = fly(o, ds);
    const auto& st = r.stats;
    fmt::print("flight {:.0f} s over {} tiles at 1280x720, CNN {}, budget {} MB: {} frames\n", o.flight_s,
               ds.tiles.size(), o.cnn ? "on" : "off", o.memory_mb, r.frame_ms.size());
    fmt::print("frame ms: median {:.1f}, p95 {:.1f}, worst {:.1f}; frames over 100 ms: {}\n",
               percentile(r.frame_ms, 0.5), percentile(r.frame_ms, 0.95), percentile(r.frame_ms, 1.0),
               over_100ms(r.frame_ms));
    if (!r.slow.empty()) fmt::print("frames over 100 ms: {}\n", fmt::join(r.slow, ", "));
    fmt::print("waiting for the scheduler, ms: set_camera median {:.3f}, worst {:.3f}; snapshot median {:.3f}, "
               "worst {:.3f}; waits over 100 ms: {}\n",
               percentile(r.camera_ms, 0.5), percentile(r.camera_ms, 1.0), percentile(r.snapshot_ms, 0.5),
               percentile(r.snapshot_ms, 1.0), over_100ms(r.camera_ms) + over_100ms(r.snapshot_ms));
    fmt::print("memory: peak RSS {} MB ({} MB before the scheduler), scheduler peak {} MB of {} MB\n",
               r.peak_rss >> 20, r.rss_before >> 20, st.peak_bytes_used >> 20, st.memory_budget >> 20);
    const std::uint64_t metadata = dataset::metadata_bytes(ds);
    fmt::print("dataset metadata: {} MB counted, {} bytes per tile\n", metadata >> 20, metadata / ds.tiles.size());
    fmt::print("at the end: {} of {} tiles' chunk points, {} linear + {} CNN heightmaps, {} full-res tiles resident "
               "({} points), {} released\n",
               st.tiles_loaded.done, st.tiles_loaded.total, st.heightmaps_linear, st.heightmaps_cnn, st.full_res_tiles,
               st.full_res_points, st.full_res_released);
    return 0;
}

// --scaling: the flight over each dataset of PATH... in turn (e.g. virtual replicas of 2,025,
// 19,600 and 152,100 tiles), one table; the first one's median is the reference of the ratios.
int scaling(const Options& o) {
    fmt::print("flight {:.0f} s at 1280x720, CNN {}, budget {} MB, {} render threads\n", o.flight_s,
               o.cnn ? "on" : "off", o.memory_mb, pool_threads(o));
    fmt::print("| tiles | frames | median ms | x first | p95 ms | worst ms | frames > 100 ms | set_camera median / "
               "worst ms | snapshot median / worst ms | RSS before the scheduler MB | metadata bytes per tile | peak "
               "RSS MB | tiles' chunk points in | linear heightmaps | CNN heightmaps | full-res tiles |\n");
    fmt::print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    double first = 0;
    for (const auto& path : o.paths) {
        FlightResult r;
        std::uint64_t metadata = 0;
        {
            const auto ds = dataset::open_dataset({path});
            if (ds.tiles.empty()) throw Error(path, std::nullopt, "no readable tiles");
            metadata = dataset::metadata_bytes(ds) / ds.tiles.size();
            r = fly(o, ds);
        }
        trim_heap();  // the next dataset's "before" starts from what this one gave back
        const double median = percentile(r.frame_ms, 0.5);
        if (first == 0) first = median;
        const auto& st = r.stats;
        fmt::print("| {} | {} | {:.1f} | {:.2f} | {:.1f} | {:.1f} | {} | {:.3f} / {:.1f} | {:.3f} / {:.1f} | {} | {} "
                   "| {} | {} of {} | {} | {} | {} |\n",
                   r.tiles, r.frame_ms.size(), median, median / first, percentile(r.frame_ms, 0.95),
                   percentile(r.frame_ms, 1.0), over_100ms(r.frame_ms), percentile(r.camera_ms, 0.5),
                   percentile(r.camera_ms, 1.0), percentile(r.snapshot_ms, 0.5), percentile(r.snapshot_ms, 1.0),
                   r.rss_before >> 20, metadata, r.peak_rss >> 20, st.tiles_loaded.done, st.tiles_loaded.total,
                   st.heightmaps_linear, st.heightmaps_cnn, st.full_res_tiles);
        std::fflush(stdout);
    }
    return 0;
}

struct NamedCamera {
    std::string name;
    render::Camera camera;
};

// Looking north at the centre of the dataset's bounds (at its middle height), `pitch_deg` down,
// from where the image is `width_m` wide at that point.
render::Camera view_of_centre(const dataset::Bounds& b, double width_m, double pitch_deg) {
    render::Camera c;
    c.width = 1280, c.height = 720;
    c.pitch_deg = pitch_deg;
    c.near_m = 1, c.far_m = 1e6;
    const double half_h = std::tan(0.5 * c.fov_deg * std::numbers::pi / 180) * c.width / c.height;
    const double distance = 0.5 * width_m / half_h, p = pitch_deg * std::numbers::pi / 180;
    c.x = b.centre_x();
    c.y = b.centre_y() - distance * std::cos(p);
    c.z = 0.5 * (b.min_z + b.max_z) - distance * std::sin(p);
    return c;
}

std::vector<NamedCamera> converge_cameras(const dataset::Bounds& b) {
    const double w = b.max_x - b.min_x, h = b.max_y - b.min_y;
    return {{"whole", view_of_centre(b, 1.05 * std::max(w, h * 1280 / 720), -90)},
            {"medium", view_of_centre(b, std::min(2000.0, w), -60)},
            {"close", view_of_centre(b, 300, -45)}};
}

// The cameras of converge_cameras named by --camera (all when none is).
std::vector<NamedCamera> chosen_cameras(const Options& o, const dataset::Bounds& b) {
    std::vector<NamedCamera> out;
    for (auto& c : converge_cameras(b)) {
        if (o.cameras.empty() || std::find(o.cameras.begin(), o.cameras.end(), c.name) != o.cameras.end())
            out.push_back(std::move(c));
    }
    if (out.empty()) throw std::invalid_argument("--camera names none of whole, medium, close");
    return out;
}

// The frame with every point of every visible tile: a scheduler with the default budget, idle.
render::RgbaImage reference_frame(const Options& o, const dataset::Dataset& ds, const render::Camera& camera,
                                  viewer::SceneStyle style, ThreadPool& pool) {
    viewer::SchedulerOptions so;
    so.cnn = o.cnn;
    so.camera = camera;
    viewer::Scheduler scheduler(ds, so);
    const auto t0 = Clock::now();
    while (!scheduler.idle()) {
        if (since(t0) > 600) throw std::runtime_error("the reference scheduler is not idle after 600 s");
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    const auto st = scheduler.stats();
    if (st.full_res.done != st.full_res.total) {
        fmt::print(stderr, "bench_view: reference has {} of {} visible tiles at full resolution\n", st.full_res.done,
                   st.full_res.total);
    }
    style.lod_spacing_px = 0;
    return viewer::render_snapshot(*scheduler.snapshot(), camera, style, pool).image;
}

// True when every point of the tiles `camera` sees fits in half the default budget (an all-points
// reference can be drawn).
bool all_points_fit(const dataset::Dataset& ds, const render::Camera& camera) {
    std::uint64_t bytes = 0;
    for (const auto& t : ds.tiles) {
        if (viewer::screen_fraction(camera, t.bounds_m) > 0) bytes += viewer::tile_point_set_bytes(t);
    }
    return bytes <= viewer::default_memory_budget() / 2;
}

// Prints the streamed reference's progress on stderr, at most once a second (called from the
// decoding threads).
class ReferenceBar {
public:
    explicit ReferenceBar(std::string name) : name_(std::move(name)), start_(Clock::now()) {}
    void operator()(std::uint64_t done, std::uint64_t total) {
        std::lock_guard lock(mutex_);
        if (done < total && Clock::now() - printed_ < std::chrono::seconds(1)) return;
        printed_ = Clock::now();
        const auto percent = 100.0 * static_cast<double>(done) / static_cast<double>(std::max<std::uint64_t>(1, total));
        fmt::print(stderr, "\rreference of the {} camera: {} of {} M points ({:.0f}%), {:.0f} s{}", name_,
                   done / 1000000, total / 1000000, percent, since(start_), done < total ? "" : "\n");
    }

private:
    std::string name_;
    Clock::time_point start_, printed_{};
    std::mutex mutex_;
};

// The all-points frame of a view whose points do not fit in memory: every point of the visible
// tiles streamed into it (viewer/reference_frame.hpp) over the linear heightmaps (a scheduler
// without full resolution, idle), cached in --reference-cache so that it is built once.
render::RgbaImage streamed_reference(const Options& o, const dataset::Dataset& ds, const NamedCamera& view,
                                     const viewer::SceneStyle& style, ThreadPool& pool) {
    const std::string key = viewer::reference_key(ds, view.camera, style, "linear heightmaps from chunk points");
    if (auto cached = viewer::load_reference(o.reference_cache, key)) return std::move(*cached);
    const auto t0 = Clock::now();
    viewer::SchedulerOptions so;
    so.cnn = false, so.full_res = false;
    so.heightmap_threads = pool_threads(o);
    so.camera = view.camera;
    std::shared_ptr<const viewer::SceneSnapshot> snapshot;
    {
        viewer::Scheduler scheduler(ds, so);
        while (!scheduler.idle()) std::this_thread::sleep_for(std::chrono::milliseconds(20));
        snapshot = scheduler.snapshot();
    }
    std::vector<render::HeightmapPatch> heightmaps;
    for (const auto& h : snapshot->heightmaps) heightmaps.push_back(h->view());
    fmt::print(stderr, "reference of the {} camera: {} heightmaps in {:.0f} s\n", view.name, heightmaps.size(),
               since(t0));
    ReferenceBar bar(view.name);
    auto image = viewer::stream_reference_frame(ds, view.camera, heightmaps, style, pool, std::ref(bar));
    viewer::store_reference(o.reference_cache, key, image);
    return image;
}

const std::vector<double> kSampleTimes = {0.5, 1, 2, 5, 10, 30};

// A field of /proc/self/status in bytes ("RssAnon", "RssFile"); 0 when absent.
std::uint64_t status_bytes(const std::string& field) {
    std::ifstream in("/proc/self/status");
    for (std::string line; std::getline(in, line);) {
        if (line.starts_with(field + ":")) return std::stoull(line.substr(field.size() + 1)) << 10;  // kB
    }
    return 0;
}

// What the process held when its resident size peaked: the resident size (anonymous and
// file-backed), what the scheduler counts against the budget, and the C heap's bytes in use and
// freed but kept (bytes).
struct MemoryAtPeak {
    std::uint64_t rss = 0, counted = 0, heap_in_use = 0, heap_free_kept = 0, anon = 0, file = 0;

    // Samples the process when its resident size is the highest yet by a mebibyte or more (glibc's mallinfo2 walks
    // every free chunk: taken each frame while a large dataset loads, it was 43% of a remote catalog's run).
    void sample(const viewer::Scheduler& scheduler) {
        const std::uint64_t now = resident_bytes();
        if (now < rss + (1u << 20)) return;
        const HeapUse heap = heap_use();
        *this = {now, scheduler.stats().bytes_used, heap.in_use, heap.free_kept, status_bytes("RssAnon"),
                 status_bytes("RssFile")};
    }
    std::string json() const {
        return fmt::format("{{\"rss_mb\": {}, \"anon_mb\": {}, \"file_mb\": {}, \"counted_mb\": {}, "
                           "\"heap_in_use_mb\": {}, \"heap_free_kept_mb\": {}}}",
                           rss >> 20, anon >> 20, file >> 20, counted >> 20, heap_in_use >> 20, heap_free_kept >> 20);
    }
};

// `frame` as NAME.png in `dir`, and each layer of `snapshot` alone (NAME-heightmaps.png, -chunk-points,
// -points): what each part of the frame comes from.
void write_frame_pngs(const std::string& dir, const std::string& name, const render::RgbaImage& frame,
                      const viewer::SceneSnapshot& snapshot, const render::Camera& camera,
                      const viewer::SceneStyle& style, ThreadPool& pool) {
    render::write_png(fmt::format("{}/{}.png", dir, name), frame);
    const std::pair<const char*, viewer::SceneLayers> layers[] = {
        {"heightmaps", {true, false, false}}, {"chunk-points", {false, true, false}}, {"points", {false, false, true}}};
    for (const auto& [layer, on] : layers) {
        render::write_png(fmt::format("{}/{}-{}.png", dir, name, layer),
                          viewer::render_snapshot(snapshot, camera, style, pool, on).image);
    }
}

struct LiveRun {
    std::vector<double> psnr_db;  // against the reference, at kSampleTimes
    std::uint64_t scheduler_peak = 0;
    MemoryAtPeak peak;
    std::size_t loads = 0, released = 0;  // full-resolution loads (pieces) and releases in the run
};

// A freshly opened scheduler at `camera`, drawn at 60 Hz through the FrameRefiner; the PSNR of
// the frames at the sample times against `reference` (written to --png when asked).
LiveRun live_run(const Options& o, const dataset::Dataset& ds, const NamedCamera& view, const viewer::SceneStyle& style,
                 const render::RgbaImage& reference, ThreadPool& pool) {
    viewer::SchedulerOptions so;
    so.cnn = o.cnn;
    so.memory_budget = o.memory_mb << 20;
    so.camera = view.camera;
    viewer::Scheduler scheduler(ds, so);
    viewer::FrameRefiner refiner;
    LiveRun run;
    const auto start = Clock::now();
    std::vector<double> frame_ms;
    auto next_frame = start;
    while (run.psnr_db.size() < kSampleTimes.size()) {
        std::this_thread::sleep_until(next_frame);  // a 60 Hz display
        const auto f0 = Clock::now();
        next_frame = f0 + kVsync;
        scheduler.set_camera(view.camera);
        const bool loading = scheduler.points_loading();  // before the snapshot: when false, it holds all
        const auto& frame = refiner.draw(*scheduler.snapshot(), view.camera, style, pool, {}, loading).image;
        frame_ms.push_back(1000 * since(f0));
        run.peak.sample(scheduler);
        const double t = kSampleTimes[run.psnr_db.size()];
        if (since(start) < t) continue;
        run.psnr_db.push_back(render::image_psnr_db(frame, reference));
        if (!o.png_dir.empty()) write_frame_pngs(o.png_dir, fmt::format("{}-{}s", view.name, t), frame,
                                                 *scheduler.snapshot(), view.camera, style, pool);
        const auto st = scheduler.stats();
        if (o.json) continue;
        fmt::print("{} camera at {:.1f} s: {} of {} visible tiles full, {} coarse, {} heightmaps, {} MB held ({} MB "
                   "points, {} MB decoding, the rest heightmaps and chunk points); {} loads, {} releases\n",
                   view.name, since(start), st.full_res.done, st.full_res.total, st.coarse_tiles,
                   st.heightmaps_linear + st.heightmaps_cnn, st.bytes_used >> 20, st.bytes_full_res >> 20,
                   st.bytes_decoding >> 20, st.full_res_loads, st.full_res_released);
    }
    const auto st = scheduler.stats();
    run.scheduler_peak = st.peak_bytes_used;
    run.loads = st.full_res_loads, run.released = st.full_res_released;
    if (!o.json) {
        fmt::print("{} camera frame ms (cached still frames included): median {:.1f}, worst {:.1f} ({} frames); "
                   "scheduler peak {} MB; {} loads, {} releases; at peak RSS: {}\n",
                   view.name, percentile(frame_ms, 0.5), percentile(frame_ms, 1.0), frame_ms.size(),
                   run.scheduler_peak >> 20, run.loads, run.released, run.peak.json());
    }
    return run;
}

// True when no sample is more than 0.1 dB below an earlier one.
bool never_worse(const std::vector<double>& psnr_db) {
    for (std::size_t i = 1; i < psnr_db.size(); ++i) {
        if (psnr_db[i] < *std::max_element(psnr_db.begin(), psnr_db.begin() + static_cast<std::ptrdiff_t>(i)) - 0.1)
            return false;
    }
    return true;
}

int converge(const Options& o, const dataset::Dataset& ds) {
    viewer::SceneStyle style = o.style;
    style.resolve.edl_strength = 0;
    ThreadPool pool(pool_threads(o));
    const auto views = chosen_cameras(o, ds.bounds_m);
    // Per camera the reference first, its memory returned before the live run.
    const std::uint64_t rss0 = resident_bytes();  // the dataset's headers, the code: not the scheduler's
    MemoryAtPeak peak;
    std::uint64_t scheduler_peak = 0;
    std::vector<std::string> cameras;
    for (const auto& view : views) {
        const bool fits = all_points_fit(ds, view.camera);
        const auto reference = fits ? reference_frame(o, ds, view.camera, style, pool)
                                    : streamed_reference(o, ds, view, style, pool);
        if (!o.png_dir.empty()) render::write_png(fmt::format("{}/{}-reference.png", o.png_dir, view.name), reference);
        const LiveRun run = live_run(o, ds, view, style, reference, pool);
        if (run.peak.rss > peak.rss) peak = run.peak;
        scheduler_peak = std::max(scheduler_peak, run.scheduler_peak);
        const char* kind = fits ? "all points" : "all points, streamed";
        std::vector<std::string> samples;
        for (std::size_t i = 0; i < kSampleTimes.size(); ++i) {
            samples.push_back(fmt::format("{{\"t\": {}, \"psnr_db\": {:.2f}}}", kSampleTimes[i], run.psnr_db[i]));
            if (!o.json) fmt::print("{} camera: {:.1f} s {:.2f} dB\n", view.name, kSampleTimes[i], run.psnr_db[i]);
        }
        if (!o.json) fmt::print("{} camera: reference {}; never worse over time: {}\n", view.name, kind,
                                never_worse(run.psnr_db) ? "yes" : "no");
        cameras.push_back(fmt::format("{{\"name\": \"{}\", \"reference\": \"{}\", \"samples\": [{}], "
                                      "\"never_worse\": {}, \"loads\": {}, \"releases\": {}, \"at_peak_rss\": {}}}",
                                      view.name, kind, fmt::join(samples, ", "), never_worse(run.psnr_db), run.loads,
                                      run.released, run.peak.json()));
    }
    const std::string dataset = fmt::format("{}", fmt::join(o.paths, " "));
    if (o.json) {
        fmt::print("{{\"dataset\": \"{}\", \"cameras\": [{}], \"peak_rss_mb\": {}, \"budget_mb\": {}, "
                   "\"scheduler_peak_mb\": {}, \"rss_before_mb\": {}}}\n",
                   dataset, fmt::join(cameras, ", "), peak.rss >> 20, o.memory_mb, scheduler_peak >> 20, rss0 >> 20);
    } else {
        fmt::print("peak RSS {} MB (live runs; {} MB before the first scheduler), scheduler peak {} MB, budget {} MB\n",
                   peak.rss >> 20, rss0 >> 20, scheduler_peak >> 20, o.memory_mb);
    }
    return 0;
}

// CPU seconds this process has used (every thread, user and system).
double cpu_seconds() {
    rusage u{};
    ::getrusage(RUSAGE_SELF, &u);
    const auto s = [](const timeval& t) {
        return static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_usec);
    };
    return s(u.ru_utime) + s(u.ru_stime);
}

int load_cost(const Options& o, const dataset::Dataset& ds) {
    for (const auto& view : converge_cameras(ds.bounds_m)) {
        std::vector<double> wall, cpu;
        std::size_t full = 0, wanted = 0;
        for (int run = 0; run < std::max(1, o.runs); ++run) {
            viewer::SchedulerOptions so;
            so.cnn = o.cnn;
            so.memory_budget = o.memory_mb << 20;
            so.camera = view.camera;
            const double c0 = cpu_seconds();
            const auto t0 = Clock::now();
            {
                viewer::Scheduler scheduler(ds, so);
                while (!scheduler.idle()) std::this_thread::sleep_for(std::chrono::milliseconds(5));
                wall.push_back(since(t0));
                cpu.push_back(cpu_seconds() - c0);
                const auto st = scheduler.stats();
                full = st.full_res.done, wanted = st.full_res.total;
            }
        }
        fmt::print("{} camera: idle after {:.2f} s wall, {:.2f} CPU s (medians of {}); {} of {} visible tiles full\n",
                   view.name, percentile(wall, 0.5), percentile(cpu, 0.5), wall.size(), full, wanted);
    }
    return 0;
}

// --soak: bench/view_soak.hpp with this run's options.
int soak(const Options& o, const dataset::Dataset& ds) {
    bench::SoakSettings s;
    s.minutes = o.soak_minutes, s.csv = o.soak_csv, s.action_every_s = o.soak_action_every_s;
    s.budget = o.memory_mb << 20, s.threads = pool_threads(o), s.cnn = o.cnn, s.style = o.style;
    return bench::run_soak(ds, s);
}

}  // namespace

constexpr const char* kUsage =
    "PATH... [--flight SECONDS [--scaling R1 R2 ...]] [--converge [--camera NAME]... [--png DIR] "
    "[--reference-cache DIR]] [--load-cost] [--soak MINUTES [--soak-csv FILE] [--soak-action-every S]] "
    "[--cnn] [--memory MB] [--threads N] [--lod-spacing PX] "
    "[--backend cpu|cuda|auto] [--classes C] [--returns R] [--intensity MIN-MAX] [--runs N] [--json]";

int main(int argc, char** argv) {
    return lidarscout::bench::bench_main("bench_view", kUsage, argc, argv, [](int argc, char** argv) {
        const Options o = parse(argc, argv);
        if (o.scaling) {
            if (o.flight_s <= 0) throw std::invalid_argument("--scaling needs --flight SECONDS");
            return scaling(o);
        }
        const auto t0 = Clock::now();
        const auto ds = dataset::open_dataset(o.paths);
        const double headers = since(t0);
        for (const auto& skipped : ds.skipped) fmt::print(stderr, "bench_view: skipped {}\n", skipped.error);
        if (ds.tiles.empty()) throw Error("no readable tiles in the paths given: nothing to measure");
        if (o.converge) return converge(o, ds);
        if (o.load_cost) return load_cost(o, ds);
        if (o.soak_minutes > 0) return soak(o, ds);
        return o.flight_s > 0 ? flight(o, ds) : loading(o, ds, headers);
    });
}
