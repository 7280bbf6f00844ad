// `lidarscout serve PATH... [--listen HOST:PORT] [--token T] [--memory SIZE] [--cors ORIGIN] [--model FILE]`:
// the datasets as a web page (src/serve, web/): a small HTTP server on loopback by default
// (any other address needs --token) that prints its URL as the first line of stdout once it
// listens, then serves until stopped (Ctrl-C).
#include <CLI/CLI.hpp>

#include <malloc.h>

#include <algorithm>
#include <cstdio>
#include <memory>
#include <thread>

#include "cli/commands.hpp"
#include "cli/io_options.hpp"
#include "cli/size_options.hpp"
#include "cli/stage_progress.hpp"
#include "core/error.hpp"
#include "dataset/dataset.hpp"
#include "nn/heightmap_network.hpp"
#include "serve/server.hpp"
#include "viewer/scheduler.hpp"

namespace lidarscout::cli {
namespace {

struct ServeCliOptions {
    std::vector<std::string> paths;
    std::string listen = "127.0.0.1:0";
    std::string token;
    std::string memory;
    std::string cors;
    std::string crs;
    std::string web;
    std::string model;
    bool no_cnn = false;
};

// The network's file: --model, else the shipped model when it is found; empty (linear heightmaps
// only) with --no-cnn or without a model, said in one line.
std::string model_path(const ServeCliOptions& o) {
    if (o.no_cnn) return {};
    if (!o.model.empty()) {
        nn::check_model_file(o.model);
        return o.model;
    }
    try {
        return nn::default_model_path();
    } catch (const Error& e) {
        std::fprintf(stderr, "lidarscout: %s; linear heightmaps only\n", e.what());
        return {};
    }
}

constexpr std::uint64_t kMinCacheBytes = 16ull << 20;
constexpr std::uint64_t kGridBytesPerChunkPoint = 40;  // PatchGrid's 24-byte points with its vectors' slack
constexpr std::uint64_t kBaseBytes = 96ull << 20;      // the program, its libraries and the server's threads

// How --memory is shared: the chunk points' grid and the process first, then the tiles decoded at
// once for their levels of detail (two when two fit beside a cache as large and the machine has four
// cores, else one), the rest
// the response cache.
struct MemoryShares {
    int decode_slots = 1;
    std::uint64_t cache = kMinCacheBytes;
};

MemoryShares share_memory(std::uint64_t memory, const dataset::Dataset& ds) {
    std::uint64_t largest = 0;
    for (const auto& t : ds.tiles) largest = std::max(largest, t.tile.header.point_count);
    const std::uint64_t decode = largest * serve::kDecodeBytesPerPoint;
    const std::uint64_t fixed = kBaseBytes + ds.chunk_point_count * kGridBytesPerChunkPoint;
    const std::uint64_t left = memory > fixed ? memory - fixed : 0;
    MemoryShares s;
    // (and at most half the cores: the rest answer the cheap requests, overviews and heightmaps, at once)
    const unsigned half_cores = std::max(1u, std::thread::hardware_concurrency() / 2);
    s.decode_slots = left >= 4 * decode && half_cores >= 2 ? 2 : 1;
    const std::uint64_t decoding = s.decode_slots * decode;
    s.cache = std::max(kMinCacheBytes, left > decoding ? left - decoding : 0);
    return s;
}

// The server's allocations come and go with requests on many threads: large blocks from mmap (given
// back when freed) and few arenas, so that the resident size follows what is held (the CLI's
// default keeps freed memory for the heightmap jobs of one process-long pass).
void return_freed_memory() {
    mallopt(M_MMAP_THRESHOLD, 256 << 10);
    mallopt(M_TRIM_THRESHOLD, 1 << 20);
    mallopt(M_ARENA_MAX, 4);
}

int run_serve(const ServeCliOptions& o) {
    serve::ServerOptions options;
    options.listen = serve::parse_listen_address(o.listen);
    options.token = o.token;
    options.cors_origin = o.cors;
    serve::check_access_rule(options.listen, options.token);  // before anything is read
    return_freed_memory();
    options.web_dir = o.web.empty() ? serve::default_web_dir() : o.web;
    const std::uint64_t memory = o.memory.empty() ? viewer::default_memory_budget() : parse_bytes(o.memory);
    const std::string model = model_path(o);
    dataset::DatasetOptions dataset_options;
    dataset_options.crs = o.crs;
    auto ds = open_with_progress(o.paths, dataset_options);
    for (const auto& s : ds.skipped) std::fprintf(stderr, "lidarscout: skipped %s\n", s.error.c_str());
    dataset::require_tiles(ds, "serve");
    const MemoryShares shares = share_memory(memory, ds);
    options.memory_budget = shares.cache;
    auto cache = std::make_unique<serve::ResponseCache>(options.memory_budget);
    std::vector<std::unique_ptr<serve::Survey>> surveys;
    surveys.push_back(std::make_unique<serve::Survey>(std::move(ds), *cache, shares.decode_slots));
    surveys.back()->set_model(model);
    serve::Server server(std::move(surveys), options, std::move(cache));
    server.bind();
    std::printf("%s\n", server.url().c_str());
    std::fflush(stdout);
    server.run();
    return 0;
}

}  // namespace

void register_serve_command(CLI::App& app, std::function<int()>& run) {
    auto o = std::make_shared<ServeCliOptions>();
    auto* cmd = app.add_subcommand("serve", "Serve datasets as a web page (WebGL2) and a binary API, with no "
                                            "conversion; prints the page's URL first");
    add_inputs(*cmd, "paths", o->paths, kDatasetPathsHelp)->required();
    cmd->add_option("--listen", o->listen,
                    "HOST:PORT to listen on (default 127.0.0.1:0: loopback, a free port); an address other than "
                    "loopback needs --token");
    cmd->add_option("--token", o->token,
                    "A secret every request must carry (?token= or Authorization: Bearer); the URL printed holds it");
    cmd->add_option("--memory", o->memory,
                    "Memory for the server: the chunk points and the shared cache of encoded responses, e.g. 2G "
                    "(default: a quarter of the RAM)");
    cmd->add_option("--cors", o->cors, "Allow pages of this origin (e.g. https://example.org) to use the API");
    cmd->add_option("--crs", o->crs,
                    "Reproject every tile to this CRS, e.g. EPSG:32632 (default: the CRS most tiles use)");
    cmd->add_option("--model", o->model,
                    "TorchScript heightmap network for the page's second heightmaps (default: "
                    "models/heightmap_cnn.pt when found)");
    cmd->add_flag("--no-cnn", o->no_cnn, "Linear heightmaps only (no network)");
    cmd->add_option("--web", o->web, "The page's folder (default: web/ of the installation or source tree)");
    cmd->callback([o, &run] { run = [o] { return run_serve(*o); }; });
}

}  // namespace lidarscout::cli
