// Benchmark: the overview of a remote dataset (issue 18). nginx serves a local dataset folder
// on loopback; a delaying proxy in front of it adds a round-trip latency (each direction
// delayed by half of it; tc netem needs a kernel module that is not always there). For each
// latency: seconds for all headers and chunk tables, seconds and rate for all chunk points,
// HTTP requests (per tile), and bytes moved (response bodies and headers) against the bytes
// of the dataset. Every run starts cold: no open remote file, no range cache.
// With --view PROGRAM, the viewer instead: for each latency `PROGRAM view` opens the tile list
// (cold: --cache-size 0) and quits --view-seconds (default 5) after the dataset is open; it reports the seconds from
// its start to the first frame presented, to the first with every tile's footprint, to the dataset
// open, to the first frame with heightmaps and to the first with all chunk points (view --stats-json). Run it under
// `xvfb-run -a` (or on a display).
// Every figure is the median of --runs runs (default 3).
// With --https, nginx is reached over TLS and HTTP/2 (its test CA trusted): one multiplexed
// connection instead of a pool of HTTP/1.1 ones.
// With --s3, the tiles are served by the tests' S3 server (tests/s3_server.hpp, signed requests,
// its store linked to FOLDER's files) as s3://bench/, behind the same proxy; with --vpc PROGRAM
// too, the dataset is the QGIS virtual point cloud `PROGRAM catalog s3://bench/` writes (its
// items place every tile before any header is read). --s3-copies N serves FOLDER's tiles N times
// over (keys copyK/...: N x the tiles, each copy where the original lies) for a catalog of
// thousands of items from a small folder.
// With --replica MANIFEST instead of FOLDER, a virtual replica (`synth replicate --virtual`) served by
// the replica object server (tests/replica_server.hpp: 152,100 tiles cost it nothing), one per latency
// with that round trip (and --bandwidth bytes/s per connection): the dataset is its catalog.vpc, or
// with --s3 its bucket's listing (s3://replica/). Each latency adds what the server counted per run:
// tile requests per tile, multi-range requests, catalog requests and bytes, listing pages, GETs per
// chunk (tile requests per chunk point: a LAZ tile's chunk points are its chunks' first points), and
// overview requests. With --overview FILE (an overview sidecar: `lidarscout catalog MANIFEST -o OUT.vpc
// --overview`) the server serves it and its catalog names it.
// --merge-gaps 0,16384,... runs each latency once per merge gap (HttpSettings::merge_gap_one_range, the
// bytes up to which two ranges of a read go as one to a server that answers one range per request), and
// first prints, from the replica's source tiles' chunk tables, what each gap (those and 0 to 16 MiB)
// costs: the chunk-point reads (requests) a tile makes against the bytes read between them (waste), the
// seconds both take at 50 ms a request with 256 in flight and at 100 MB/s, and the request fees against
// the egress fees of S3's price list ($0.0004 per 1,000 GETs, $0.09 per GB).
// Usage: bench_http [--runs N] [--rtt-ms 0,20,50] [--https | --s3 [--s3-copies N] [--vpc PROGRAM]]
//                   [--view PROGRAM [--view-args "..."] [--view-seconds S]] FOLDER
//        bench_http [--runs N] [--rtt-ms 0,20,50] [--s3] [--bandwidth BYTES_PER_S] [--merge-gaps 0,16384]
//                   [--view PROGRAM [--view-args "..."] [--view-seconds S]] [--overview FILE] --replica MANIFEST
#include <fmt/format.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "bench_main.hpp"
#include "bench_timing.hpp"
#include "core/error.hpp"
#include "dataset/chunk_point_loader.hpp"
#include "dataset/chunk_points.hpp"
#include "dataset/dataset.hpp"
#include "dataset/file_search.hpp"
#include "dataset/tile.hpp"
#include "dataset/virtual_replica.hpp"
#include "io/file.hpp"
#include "net/byte_ranges.hpp"
#include "core/patch_grid.hpp"
#include "net/http_client.hpp"
#include "net/range_cache.hpp"
#include "net/remote_file.hpp"
#include "delay_proxy.hpp"
#include "net/s3_config.hpp"
#include "nginx_server.hpp"
#include "replica_server.hpp"
#include "s3_server.hpp"

using namespace lidarscout;

namespace {

using bench::Clock;
using bench::median;
using bench::seconds_since;

struct Run {
    double headers = 0, chunk_points = 0, rate = 0;
    std::uint64_t requests = 0, header_requests = 0, retries = 0, bytes = 0, tiles = 0, points = 0;
    std::uint64_t http2 = 0, connections = 0;
};

Run run_once(const std::string& list_url) {
    net::RemoteFile::forget_all();
    const auto before = net::HttpClient::shared().stats();
    Run r;
    auto t0 = Clock::now();
    const auto ds = dataset::open_dataset({list_url});
    r.headers = seconds_since(t0);
    r.header_requests = net::HttpClient::shared().stats().requests - before.requests;
    r.tiles = ds.tiles.size();
    if (!ds.skipped.empty()) throw Error(ds.skipped.front().path + ": " + ds.skipped.front().error);
    const auto [ox, oy] = dataset::patch_grid_origin(ds);
    lidarscout::PatchGrid grid(ox, oy);
    dataset::ChunkPointLoader loader(ds, grid);
    t0 = Clock::now();
    loader.start();
    loader.wait();
    r.chunk_points = seconds_since(t0);
    r.points = loader.loaded();
    if (loader.failed() > 0) throw Error("chunk points failed: " + loader.errors().front().message());
    r.rate = static_cast<double>(r.points) / r.chunk_points;
    const auto after = net::HttpClient::shared().stats();
    r.requests = after.requests - before.requests;
    r.retries = after.retries - before.retries;
    r.http2 = after.http2_responses - before.http2_responses;
    r.connections = after.connections - before.connections;
    r.bytes = (after.body_bytes - before.body_bytes) + (after.header_bytes - before.header_bytes);
    return r;
}

struct ViewRun {
    double first_frame = 0, open = 0, frames_while_opening = 0;
    std::optional<double> footprints, overview, chunk_points;  // unset: not within the run (or not reported)
};

double seconds_field(const nlohmann::json& j, const char* key) {
    const auto& v = j.at(key);
    if (v.is_null()) throw Error(std::string("view never reached ") + key);
    return v.get<double>();
}

// One cold `view` of `url`, quitting `quit_after` seconds after the dataset is open.
ViewRun view_once(const std::string& program, const std::string& args, const std::string& url, double quit_after) {
    const auto stats =
        std::filesystem::temp_directory_path() / ("bench_http_view_" + std::to_string(::getpid()) + ".json");
    const std::string cmd = program + " view '" + url + "' --cache-size 0 --size 960x540 --quit-after " +
                            std::to_string(quit_after) + " --stats-json " +
                            stats.string() + " " + args + " >/dev/null 2>&1";
    if (std::system(cmd.c_str()) != 0) throw Error("failed: " + cmd);
    std::ifstream in(stats);
    const auto j = nlohmann::json::parse(in);
    std::filesystem::remove(stats);
    ViewRun r{seconds_field(j, "first_frame_s"), seconds_field(j, "dataset_open_s"),
              j.at("frames_while_opening").get<double>(), std::nullopt, std::nullopt};
    if (j.contains("footprints_s") && !j.at("footprints_s").is_null()) {  // absent from older viewers
        r.footprints = j.at("footprints_s").get<double>();
    }
    if (!j.at("first_overview_s").is_null()) r.overview = j.at("first_overview_s").get<double>();
    if (!j.at("chunk_points_s").is_null()) r.chunk_points = j.at("chunk_points_s").get<double>();
    return r;
}

void bench_view(const std::string& program, const std::string& args, const std::string& url, int rtt, int runs,
                double quit_after) {
    std::vector<double> first, footprints, open, overview, points, frames;
    for (int k = 0; k < runs; ++k) {
        const ViewRun r = view_once(program, args, url, quit_after);
        first.push_back(r.first_frame), open.push_back(r.open);
        if (r.footprints) footprints.push_back(*r.footprints);
        if (r.overview) overview.push_back(*r.overview);
        frames.push_back(r.frames_while_opening);
        if (r.chunk_points) points.push_back(*r.chunk_points);
    }
    fmt::print("rtt {:>3} ms: view: first frame {:.3f} s; every footprint {:.3f} s (in {} of {} runs); dataset open "
               "{:.3f} s ({:.0f} frames before); first overview {:.3f} s (in {} of {} runs); all chunk points {:.3f} s "
               "(in {} of {} runs)\n",
               rtt, median(first), median(footprints), footprints.size(), runs, median(open), median(frames),
               median(overview), overview.size(), runs, median(points), points.size(), runs);
}

// Writes the server's lists/tiles.txt naming every tile of `folder` (relative URLs); returns
// its path on the server and adds the tiles' bytes to `dataset_bytes`.
std::string write_tile_list(const test::NginxServer& server, const std::filesystem::path& folder,
                            std::uint64_t& dataset_bytes) {
    std::ofstream list(server.lists_dir() / "tiles.txt");
    for (const auto& f : dataset::find_point_cloud_files({folder.string()}).files) {
        list << "../" << std::filesystem::relative(f, folder).string() << "\n";
        dataset_bytes += std::filesystem::file_size(f);
    }
    return "lists/tiles.txt";
}

// An S3 server whose bucket "bench" holds FOLDER's tiles `copies` times (links, nothing copied).
std::unique_ptr<test::S3Server> s3_server_of(const std::filesystem::path& folder, int copies,
                                             std::uint64_t& dataset_bytes) {
    const auto tiles = dataset::find_point_cloud_files({folder.string()}).files;
    return std::make_unique<test::S3Server>(std::vector<std::string>{"bench"}, [&](const std::filesystem::path& data) {
        for (int k = 0; k < copies; ++k) {
            const std::string prefix = copies > 1 ? "copy" + std::to_string(k) + "/" : "";
            for (const auto& f : tiles) {
                test::S3Server::link_object(data, "bench", prefix + std::filesystem::relative(f, folder).string(), f);
                dataset_bytes += std::filesystem::file_size(f);
            }
        }
    });
}

// s3:// requests (here and in the programs run) signed for the S3 server, through the proxy at `port`.
void use_s3_endpoint(int port) {
    const std::string endpoint = "http://127.0.0.1:" + std::to_string(port);
    ::setenv("AWS_ENDPOINT_URL", endpoint.c_str(), 1);
    ::setenv("AWS_ACCESS_KEY_ID", test::S3Server::kKey, 1);
    ::setenv("AWS_SECRET_ACCESS_KEY", test::S3Server::kSecret, 1);
    ::setenv("AWS_SHARED_CREDENTIALS_FILE", "/dev/null", 1);
    net::set_s3_config(std::nullopt);  // read again
}

// The VPC `program catalog` writes of the S3 bucket (a temporary file).
std::string write_vpc(const std::string& program) {
    const auto vpc = std::filesystem::temp_directory_path() / ("bench_http_" + std::to_string(::getpid()) + ".vpc");
    std::filesystem::remove(vpc);
    const std::string cmd = program + " catalog s3://bench/ -o " + vpc.string() + " >/dev/null 2>&1";
    if (std::system(cmd.c_str()) != 0) throw Error("failed: " + cmd);
    return vpc.string();
}

// The replica's bytes as if copied: each tile's source size.
std::uint64_t replica_bytes(const std::string& manifest) {
    std::map<std::string, std::uint64_t> sizes;
    std::uint64_t total = 0;
    for (const auto& t : dataset::read_virtual_replica(manifest)) {
        auto [at, added] = sizes.try_emplace(t.path, 0);
        if (added) at->second = std::filesystem::file_size(t.path);
        total += at->second;
    }
    return total;
}

struct Options {
    int runs = 3;
    std::vector<int> rtts = {0, 20, 50};
    std::string folder, replica, view_program, view_args, vpc_program, overview;
    bool https = false, s3 = false;
    int s3_copies = 1;
    std::uint64_t bandwidth = 0;
    double view_seconds = 5;
    std::vector<int> merge_gaps;  // empty: the default gap only
};

std::vector<int> parse_list(const std::string& list) {
    std::vector<int> out;
    for (std::size_t at = 0; at <= list.size();) {
        const auto comma = std::min(list.find(',', at), list.size());
        out.push_back(std::atoi(list.substr(at, comma - at).c_str()));
        at = comma + 1;
    }
    return out;
}

Options parse_options(int argc, char** argv) {
    Options o;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        const bool value = i + 1 < argc;
        if (a == "--runs" && value) {
            o.runs = std::max(1, std::atoi(argv[++i]));
        } else if (a == "--rtt-ms" && value) {
            o.rtts = parse_list(argv[++i]);
        } else if (a == "--https") {
            o.https = true;
        } else if (a == "--s3") {
            o.s3 = true;
        } else if (a == "--s3-copies" && value) {
            o.s3_copies = std::max(1, std::atoi(argv[++i]));
        } else if (a == "--vpc" && value) {
            o.vpc_program = argv[++i];
        } else if (a == "--overview" && value) {
            o.overview = argv[++i];
        } else if (a == "--replica" && value) {
            o.replica = argv[++i];
        } else if (a == "--merge-gaps" && value) {
            o.merge_gaps = parse_list(argv[++i]);
        } else if (a == "--bandwidth" && value) {
            o.bandwidth = std::stoull(argv[++i]);
        } else if (a == "--view" && value) {
            o.view_program = argv[++i];
        } else if (a == "--view-seconds" && value) {
            o.view_seconds = std::max(0.5, std::atof(argv[++i]));
        } else if (a == "--view-args" && value) {
            o.view_args = argv[++i];
        } else {
            o.folder = a;
        }
    }
    return o;
}

// The runs of one latency against `url`: medians of the figures run_once measures.
void bench_overview(const Options& o, const std::string& url, int rtt, std::uint64_t dataset_bytes) {
    std::vector<double> headers, points, rate, requests, header_requests, retries, bytes;
    Run last;
    std::uint64_t first_connections = 0;  // the first run's (later ones reuse them)
    for (int k = 0; k < o.runs; ++k) {
        last = run_once(url);
        if (k == 0) first_connections = last.connections;
        headers.push_back(last.headers);
        points.push_back(last.chunk_points);
        rate.push_back(last.rate);
        requests.push_back(static_cast<double>(last.requests));
        header_requests.push_back(static_cast<double>(last.header_requests));
        retries.push_back(static_cast<double>(last.retries));
        bytes.push_back(static_cast<double>(last.bytes));
    }
    fmt::print("rtt {:>3} ms: {} tiles, {} chunk points; headers+chunk tables {:.3f} s; chunk points {:.3f} s "
               "({:.0f}/s); {:.0f} requests ({:.2f}/tile; {:.0f} before the chunk points, {:.0f} retries); "
               "{:.1f} MB moved of {:.1f} GB ({:.4f}%); {} connections opened in the first run; "
               "{} HTTP/2 responses\n",
               rtt, last.tiles, last.points, median(headers), median(points), median(rate), median(requests),
               median(requests) / static_cast<double>(std::max<std::uint64_t>(1, last.tiles)),
               median(header_requests), median(retries),
               median(bytes) / 1e6, static_cast<double>(dataset_bytes) / 1e9,
               100.0 * median(bytes) / static_cast<double>(dataset_bytes), first_connections, last.http2);
}

// What the replica server counted over `runs` runs, per run.
void print_server_stats(const nlohmann::json& stats, int runs, double chunks) {
    const auto per_run = [&](const char* kind, const char* what) {
        return stats.at("kinds").at(kind).at(what).get<double>() / runs;
    };
    const double tiles = std::max(1.0, stats.at("tiles").get<double>());
    const double tile_requests = per_run("tile", "requests") + per_run("tile_head", "requests") +
                                 per_run("s3_object", "requests") + per_run("s3_head", "requests");
    fmt::print("         server, per run: {:.3f} tile requests/tile ({:.3f} a chunk, {:.0f} multi-range), "
               "{:.0f} catalog requests ({:.1f} MB), {:.0f} listing pages, {:.1f} MB of tiles sent, {:.0f} overview "
               "requests ({:.1f} MB)\n",
               tile_requests / tiles, tile_requests / std::max(1.0, chunks),
               stats.at("multi_range_requests").get<double>() / runs,
               per_run("catalog", "requests"), per_run("catalog", "bytes") / 1e6, per_run("s3_list", "requests"),
               (per_run("tile", "bytes") + per_run("s3_object", "bytes")) / 1e6, per_run("overview", "requests"),
               per_run("overview", "bytes") / 1e6);
}

// The chunk-point ranges of the replica's tiles, by source (every tile of a source reads the same
// ranges), and how many tiles each source has.
struct SourceReads {
    std::vector<net::ByteRange> ranges;
    std::uint64_t tiles = 0;
};

std::map<std::string, SourceReads> chunk_point_reads(const std::string& manifest) {
    std::map<std::string, SourceReads> out;
    for (const auto& t : dataset::read_virtual_replica(manifest)) {
        auto [at, added] = out.try_emplace(t.path);
        ++at->second.tiles;
        if (!added) continue;
        const auto tile = dataset::read_tile(io::File::open(t.path));
        for (const auto& l : dataset::chunk_point_locations(tile)) {
            at->second.ranges.push_back({l.offset, tile.header.record_length});
        }
    }
    return out;
}

// What each merge gap costs the replica's chunk-point reads (one range per request): requests and
// bytes wasted per tile, and both as seconds (50 ms a request, 256 in flight; 100 MB/s) and as S3 fees.
void print_merge_figures(const std::string& manifest, std::vector<int> gaps) {
    for (const int g : {0, 4096, 16384, 65536, 262144, 1 << 20, 4 << 20, 16 << 20}) gaps.push_back(g);
    std::sort(gaps.begin(), gaps.end());
    gaps.erase(std::unique(gaps.begin(), gaps.end()), gaps.end());
    const auto sources = chunk_point_reads(manifest);
    double tiles = 0, chunks = 0;
    for (const auto& [path, s] : sources) tiles += s.tiles, chunks += s.tiles * static_cast<double>(s.ranges.size());
    fmt::print("merge gaps over {:.0f} tiles ({:.1f} chunks a tile), one range per request:\n", tiles, chunks / tiles);
    for (const int gap : gaps) {
        double requests = 0, waste = 0;
        for (const auto& [path, s] : sources) {
            const auto merged = net::merge_ranges(s.ranges, static_cast<std::uint64_t>(gap));
            requests += s.tiles * static_cast<double>(merged.spans.size());
            waste += s.tiles * static_cast<double>(merged.waste);
        }
        const double request_s = requests * 0.050 / 256, waste_s = waste / 100e6;
        const double fees = requests * 0.0004 / 1000 + waste * 0.09 / 1e9;
        fmt::print("  gap {:>8} B: {:6.2f} requests/tile ({:.3f} a chunk), {:9.1f} KB wasted/tile; for all tiles "
                   "{:7.1f} s of requests + {:7.1f} s of waste, ${:.2f} in fees\n",
                   gap, requests / tiles, requests / chunks, waste / tiles / 1e3, request_s, waste_s, fees);
    }
}

// The chunk points of the replica's tiles (a LAZ tile's chunks).
double replica_chunks(const std::string& manifest) {
    double chunks = 0;
    for (const auto& [path, s] : chunk_point_reads(manifest)) chunks += s.tiles * static_cast<double>(s.ranges.size());
    return chunks;
}

// --replica: for each latency a replica server with that round trip; its catalog (or, with --s3, its
// bucket's listing) is the dataset. With --merge-gaps, one run of each latency per gap.
void run_replica(const Options& o) {
    const std::uint64_t dataset_bytes = replica_bytes(o.replica);
    if (!o.merge_gaps.empty()) print_merge_figures(o.replica, o.merge_gaps);
    const double chunks = replica_chunks(o.replica);
    std::vector<int> gaps = o.merge_gaps;
    if (gaps.empty()) gaps.push_back(-1);  // the default
    for (const int rtt : o.rtts) {
        test::ReplicaServer::Options so;
        so.rtt_ms = rtt;
        so.bandwidth = o.bandwidth;
        so.overview = o.overview;
        test::ReplicaServer server(o.replica, so);
        if (o.s3) use_s3_endpoint(server.port());
        const std::string url = o.s3 ? server.s3_url() : server.catalog_url();
        for (const int gap : gaps) {
            net::HttpSettings settings = net::HttpClient::shared().settings();
            if (gap >= 0) settings.merge_gap_one_range = static_cast<std::uint64_t>(gap);
            net::HttpClient::shared().set_settings(settings);
            fmt::print("merge gap {} B (one range per request):\n", settings.merge_gap_one_range);
            server.stats(true);
            if (!o.view_program.empty()) {
                bench_view(o.view_program, o.view_args + " --merge-gap " + std::to_string(settings.merge_gap_one_range),
                           url, rtt, o.runs, o.view_seconds);
            } else {
                bench_overview(o, url, rtt, dataset_bytes);
            }
            print_server_stats(server.stats(), o.runs, chunks);
        }
    }
}

// A folder served by nginx (or the S3 server), behind the delaying proxy.
void run_folder(Options o) {
    test::NginxServer server(o.folder);
    if (o.https) {  // trust the server's test CA, here and in the viewer
        net::HttpSettings settings = net::HttpClient::shared().settings();
        settings.ca_file = server.ca_file().string();
        net::HttpClient::shared().set_settings(settings);
        o.view_args += " --cacert " + settings.ca_file;
    }
    std::uint64_t dataset_bytes = 0;
    const std::string list = o.s3 ? std::string() : write_tile_list(server, o.folder, dataset_bytes);
    const auto s3_server = o.s3 ? s3_server_of(o.folder, o.s3_copies, dataset_bytes) : nullptr;
    for (const int rtt : o.rtts) {
        const int upstream = o.s3 ? s3_server->port() : o.https ? server.tls_port() : server.port();
        test::DelayProxy proxy(upstream, std::chrono::microseconds(rtt * 500));
        std::string url =
            (o.https ? "https" : "http") + std::string("://127.0.0.1:") + std::to_string(proxy.port()) + "/" + list;
        if (o.s3) {
            use_s3_endpoint(proxy.port());
            url = o.vpc_program.empty() ? "s3://bench/" : write_vpc(o.vpc_program);
        }
        if (!o.view_program.empty()) {
            bench_view(o.view_program, o.view_args, url, rtt, o.runs, o.view_seconds);
        } else {
            bench_overview(o, url, rtt, dataset_bytes);
        }
    }
}

constexpr const char* kUsage =
    "[--runs N] [--rtt-ms 0,20,50] [--https | --s3 [--s3-copies N] [--vpc PROGRAM]] "
    "[--view PROGRAM [--view-args \"...\"] [--view-seconds S]] FOLDER\n"
    "       bench_http [--runs N] [--rtt-ms 0,20,50] [--s3] [--bandwidth BYTES_PER_S] [--merge-gaps 0,16384] "
    "[--view PROGRAM [--view-args \"...\"] [--view-seconds S]] --replica MANIFEST";

int run(int argc, char** argv) {
    const Options o = parse_options(argc, argv);
    if (o.folder.empty() == o.replica.empty()) {
        fmt::print(stderr, "usage: bench_http {}\n", kUsage);
        return 2;
    }
    try {
        net::RangeCache::configure({{}, 0});  // every run from the network
        if (o.replica.empty()) {
            run_folder(o);
        } else {
            run_replica(o);
        }
    } catch (const std::exception& e) {
        fmt::print(stderr, "bench_http: {}\n", e.what());
        return 1;
    }
    return 0;
}

}  // namespace

int main(int argc, char** argv) { return lidarscout::bench::bench_main("bench_http", kUsage, argc, argv, run); }
