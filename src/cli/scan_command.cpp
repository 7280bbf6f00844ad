// `lidarscout scan PATH... [--json]`: reads everything the overview needs — every tile's
// header and chunk table, then every chunk point into the patch grid — and reports how long
// each stage took, how much it found, and which files were skipped and why.
#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdio>
#include <optional>
#include <set>

#include "cli/commands.hpp"
#include "cli/json_output.hpp"
#include "cli/number_options.hpp"
#include "cli/io_options.hpp"
#include "cli/network_stats.hpp"
#include "cli/diagnostic_output.hpp"
#include "cli/stage_progress.hpp"
#include "cli/tile_json.hpp"
#include "cli/thread_options.hpp"
#include "core/error.hpp"
#include "dataset/chunk_point_loader.hpp"
#include "dataset/dataset.hpp"
#include "core/patch_grid.hpp"

namespace lidarscout::cli {
namespace {

struct ScanOptions {
    std::vector<std::string> paths;
    bool json = false;
    std::string backend = "auto";
    unsigned io_threads = 0;
    unsigned queue_depth = 64;
    bool direct = false;
    std::uint64_t stride = 50'000;
    std::vector<double> focus;
    std::string crs;
};

struct ScanResult {
    dataset::Dataset dataset;
    double seconds_headers = 0;
    double seconds_chunk_points = 0;
    std::uint64_t chunk_points = 0;
    std::uint64_t failed = 0;
    std::size_t patches = 0;
    std::size_t grid_bytes = 0;
    std::vector<ErrorRecord> errors;
    std::string backend;
    net::HttpStats network;  // the requests of remote datasets (the catalog's, the tiles')
};

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

io::ReadBackend parse_backend(const std::string& name) {
    if (name == "auto") return io::ReadBackend::Auto;
    if (name == "io_uring") return io::ReadBackend::IoUring;
    if (name == "pread") return io::ReadBackend::Pread;
    throw Error("unknown --backend '" + name + "' (auto, io_uring or pread)");
}

dataset::Dataset read_headers(const ScanOptions& o) {
    dataset::DatasetOptions opt;
    opt.las_stride = o.stride;
    opt.crs = o.crs;
    opt.placed = true;  // (a catalog's headers are then read with the chunk points, nearest the focus first)
    return open_with_progress(o.paths, opt);
}

// A placed dataset's headers were read with its chunk points: its tiles take what their headers say, and
// those that could not be read join the skipped files (leaving the chunk-point errors, which named them too).
void settle_headers(ScanResult& r) {
    if (!r.dataset.placed) return;
    dataset::ensure_all_tiles(r.dataset);  // (those the loader did not need: without points)
    dataset::settle_tiles(r.dataset);
    std::set<std::string> unreadable;
    for (const auto& s : r.dataset.skipped) unreadable.insert(s.error);
    std::erase_if(r.errors, [&](const ErrorRecord& e) { return e.file.empty() && unreadable.contains(e.cause); });
}

void load_chunk_points(const ScanOptions& o, ScanResult& r) {
    const auto [ox, oy] = dataset::patch_grid_origin(r.dataset);
    lidarscout::PatchGrid grid(ox, oy);
    dataset::ChunkPointLoaderOptions opt;
    opt.reads.backend = parse_backend(o.backend);
    opt.reads.threads = o.io_threads;
    opt.reads.queue_depth = o.queue_depth;
    opt.direct_io = o.direct;
    dataset::ChunkPointLoader loader(r.dataset, grid, opt);
    if (o.focus.size() == 2) loader.set_focus(o.focus[0], o.focus[1]);
    load_with_progress(loader);
    r.chunk_points = loader.loaded();
    r.failed = loader.failed();
    r.errors = loader.errors();
    r.backend = io::backend_name(loader.backend());
    grid.shrink_to_fit();
    r.patches = grid.cells().size();
    r.grid_bytes = grid.memory_bytes();
}

nlohmann::json bounds_json(const dataset::Bounds& b) {
    if (b.empty()) return nullptr;
    return {{"min_x", b.min_x}, {"min_y", b.min_y}, {"min_z", b.min_z},
            {"max_x", b.max_x}, {"max_y", b.max_y}, {"max_z", b.max_z}, {"unit", "metre"}};
}

void print_json(const ScanResult& r) {
    nlohmann::json skipped = nlohmann::json::array();
    for (const auto& s : r.dataset.skipped) skipped.push_back({{"path", s.path}, {"error", s.error}});
    const double rate = r.seconds_chunk_points > 0 ? r.chunk_points / r.seconds_chunk_points : 0.0;
    nlohmann::json j = {{"tiles", r.dataset.tiles.size()},
                        {"skipped", skipped},
                        {"points", r.dataset.point_count},
                        {"chunk_points", r.chunk_points},
                        {"chunk_points_failed", r.failed},
                        {"patches", r.patches},
                        {"bounds", bounds_json(r.dataset.bounds_m)},
                        {"seconds_headers", r.seconds_headers},
                        {"seconds_chunk_points", r.seconds_chunk_points},
                        {"chunk_points_per_second", rate},
                        {"grid_bytes", r.grid_bytes},
                        {"backend", r.backend},
                        {"warnings", r.dataset.warnings.messages()},
                        {"diagnostics", diagnostics_json(r.dataset.warnings)},
                        {"errors", error_list_json(r.errors)}};
    j.update(network_json(r.network, r.dataset.tiles.size()));
    print_json_answer(j);
}

void print_text(const ScanResult& r) {
    const auto& ds = r.dataset;
    for (const auto& s : ds.skipped) std::fprintf(stderr, "lidarscout: skipped %s\n", s.error.c_str());
    print_diagnostics(ds.warnings);
    for (const auto& e : r.errors) std::fprintf(stderr, "lidarscout: %s\n", e.message().c_str());
    std::printf("tiles:         %zu read, %zu skipped, %llu points\n", ds.tiles.size(), ds.skipped.size(),
                (unsigned long long)ds.point_count);
    std::printf("headers:       %.3f s\n", r.seconds_headers);
    std::printf("chunk points:  %llu in %.3f s (%.0f/s, %s)%s\n", (unsigned long long)r.chunk_points,
                r.seconds_chunk_points, r.seconds_chunk_points > 0 ? r.chunk_points / r.seconds_chunk_points : 0.0,
                r.backend.c_str(), r.failed ? fmt::format(", {} failed", r.failed).c_str() : "");
    if (r.network.requests > 0) {
        const double per = ds.tiles.empty() ? 0.0 : 1.0 / static_cast<double>(ds.tiles.size());
        const auto bytes = r.network.body_bytes + r.network.header_bytes;
        std::printf("requests:      %llu (%.2f a tile), %.1f MB (%.1f KB a tile)\n",
                    (unsigned long long)r.network.requests, r.network.requests * per, bytes / 1e6, bytes * per / 1e3);
    }
    std::printf("patches:       %zu of 640 m touched, grid memory %.1f MiB\n", r.patches, r.grid_bytes / 1048576.0);
    if (!ds.bounds_m.empty()) {
        const auto& b = ds.bounds_m;
        std::printf("bounds (m):    x %.2f .. %.2f, y %.2f .. %.2f, z %.2f .. %.2f\n", b.min_x, b.max_x, b.min_y,
                    b.max_y, b.min_z, b.max_z);
    }
}

int run_scan(const ScanOptions& o) {
    ScanResult r;
    const net::HttpStats network_before = net::HttpClient::shared().stats();
    auto t0 = std::chrono::steady_clock::now();
    r.dataset = read_headers(o);
    r.seconds_headers = seconds_since(t0);
    t0 = std::chrono::steady_clock::now();
    load_chunk_points(o, r);
    r.seconds_chunk_points = seconds_since(t0);
    settle_headers(r);
    r.network = network_since(network_before);
    if (o.json) {
        print_json(r);
    } else {
        print_text(r);
    }
    const bool every_chunk_point_failed = r.failed > 0 && r.chunk_points == 0;
    return r.dataset.tiles.empty() || every_chunk_point_failed ? 1 : 0;
}

}  // namespace

void register_scan_command(CLI::App& app, std::function<int()>& run) {
    auto o = std::make_shared<ScanOptions>();
    auto* cmd = app.add_subcommand(
        "scan", "Read every tile header and chunk point (the overview) and report timings, counts and bounds");
    add_inputs(*cmd, "paths", o->paths, kDatasetPathsHelp)->required();
    cmd->add_flag("--json", o->json, "Print the result as JSON");
    cmd->add_option("--backend", o->backend, "Chunk-point reads: auto, io_uring or pread (default auto)");
    add_thread_option(*cmd, "--io-threads", o->io_threads,
                      "io_uring rings or pread threads (default: cores / queue depth)");
    cmd->add_option("--queue-depth", o->queue_depth, "Reads in flight per io_uring ring (default 64)")
        ->check(CLI::Range(1, 4096));
    cmd->add_flag("--direct", o->direct, "Read chunk points with O_DIRECT (bypass the page cache, as a cold read)");
    cmd->add_option("--las-stride", o->stride, "Chunk-point stride for uncompressed LAS tiles (default 50000)")
        ->check(positive_number());
    cmd->add_option("--crs", o->crs,
                    "Reproject every tile to this CRS, e.g. EPSG:32632 (default: the CRS most tiles use)");
    cmd->add_option("--focus", o->focus, "Load tiles nearest to X,Y (metres) first")->delimiter(',')->expected(2);
    cmd->callback([o, &run] { run = [o] { return run_scan(*o); }; });
}

}  // namespace lidarscout::cli
