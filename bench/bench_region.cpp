// bench_region [--survey PATH] [--replica PATH] [--runs N] [--threads N] [--out FILE.laz] [--json]
// The targets of profiles and clips on real data, warm page cache (one unmeasured run first), medians
// of --runs (default 5):
// - profile: a line 3 km long (the survey's diagonal when that is shorter), 2 m wide, across the
//   survey (default ../shared/data/surveys/ky-jmo335-eastern-kentucky) through its centre: seconds to
//   the first points and to the whole profile (targets 0.5 s and 5 s), points, tiles touched and
//   decoded;
// - clip: a square of 1 km² turned by 30 degrees, centred on a corner between four tiles of a replica
//   (default /tmp/rep2025/replicate.json: `lidarscout synth replicate SURVEY --grid 45x45 --virtual`),
//   written as LAZ (--out, else a temporary file removed at the end): tiles whose bounds touch the
//   polygon's box, tiles touching the polygon, tiles decoded, points written, seconds; then the output
//   is checked against a brute-force filter of the touched tiles, each decoded on its own (every point
//   tested against the polygon, kept records re-quantized to the output's scale/offset and hashed in
//   order): count and SHA-256 of the records, "match: yes|no".
// Each timing also has its CPU seconds (user + system, all threads), comparable on a loaded machine.
// --json prints one JSON object with the same figures instead of the text.
#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <numbers>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "bench_main.hpp"
#include "bench_timing.hpp"
#include "core/polygon.hpp"
#include "core/sha256.hpp"
#include "core/thread_pool.hpp"
#include "dataset/dataset.hpp"
#include "dataset/point_reader.hpp"
#include "io/file.hpp"
#include "pipelines/clip.hpp"
#include "pipelines/profile.hpp"

namespace fs = std::filesystem;
using namespace lidarscout;
using bench::median;

namespace {

struct Options {
    std::string survey = std::string(LIDARSCOUT_DATA_DIR) + "/surveys/ky-jmo335-eastern-kentucky";
    std::string replica = "/tmp/rep2025/replicate.json";
    std::string out;
    int runs = 5;
    int threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    bool json = false;
};

// User + system CPU seconds of this process so far: comparable on a loaded machine, where wall times are not.
double cpu_seconds() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return u.ru_utime.tv_sec + u.ru_stime.tv_sec + 1e-6 * (u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

// The corridor: along the survey's diagonal through its centre, 3 km long or the diagonal's length.
pipelines::Corridor survey_corridor(const dataset::Dataset& ds) {
    const double f = ds.frame.xy_to_metres;
    const auto& b = ds.bounds_m;
    const double dx = b.max_x - b.min_x, dy = b.max_y - b.min_y, diagonal = std::hypot(dx, dy);
    const double length = std::min(3000.0, diagonal), ux = dx / diagonal, uy = dy / diagonal;
    const double cx = b.centre_x(), cy = b.centre_y();
    pipelines::Corridor c;
    c.x0 = (cx - ux * length / 2) / f, c.y0 = (cy - uy * length / 2) / f;
    c.x1 = (cx + ux * length / 2) / f, c.y1 = (cy + uy * length / 2) / f;
    c.width = 2.0 / f;
    return c;
}

nlohmann::json bench_profile(const Options& o, ThreadPool& pool) {
    const auto t0 = bench::Clock::now();
    const dataset::Dataset ds = dataset::open_dataset({o.survey});
    dataset::require_tiles(ds, "bench_region");
    const double open_seconds = bench::seconds_since(t0);
    const pipelines::Corridor corridor = survey_corridor(ds);
    std::vector<double> first, complete, cpu;
    pipelines::Profile p = pipelines::read_profile(ds, corridor, {}, pool);  // warms the page cache
    for (int k = 0; k < o.runs; ++k) {
        const double cpu0 = cpu_seconds();
        p = pipelines::read_profile(ds, corridor, {}, pool);
        cpu.push_back(cpu_seconds() - cpu0);
        first.push_back(p.seconds_to_first_points);
        complete.push_back(p.seconds);
    }
    const double f = ds.frame.xy_to_metres;
    return {{"dataset", o.survey},
            {"tiles", ds.tiles.size()},
            {"open_seconds", open_seconds},
            {"line", {corridor.x0, corridor.y0, corridor.x1, corridor.y1}},
            {"crs", ds.frame.crs},
            {"length_m", corridor.length() * f},
            {"width_m", corridor.width * f},
            {"points", p.points.size()},
            {"points_read", p.read.points_read},
            {"tiles_touched", p.read.tiles_touched.size()},
            {"tiles_decoded", p.read.tiles_decoded},
            {"seconds_to_first_points", median(first)},
            {"seconds", median(complete)},
            {"cpu_seconds", median(cpu)},
            {"runs", o.runs}};
}

// A square of 1 km² turned by 30 degrees, centred between the tile nearest the dataset's centre and
// its neighbours (on the upper right corner of its bounds plus half the gap to the next tile).
MultiPolygon clip_square(const dataset::Dataset& ds) {
    const auto& b = ds.bounds_m;
    const dataset::DatasetTile* middle = &ds.tiles[0];
    for (const auto& t : ds.tiles) {
        if (t.bounds_m.distance_xy(b.centre_x(), b.centre_y()) < middle->bounds_m.distance_xy(b.centre_x(),
                                                                                             b.centre_y())) {
            middle = &t;
        }
    }
    double gap_x = INFINITY, gap_y = INFINITY;  // to the nearest tile beyond the corner, on each axis
    const auto& m = middle->bounds_m;
    for (const auto& t : ds.tiles) {
        if (t.bounds_m.min_x > m.max_x) gap_x = std::min(gap_x, t.bounds_m.min_x - m.max_x);
        if (t.bounds_m.min_y > m.max_y) gap_y = std::min(gap_y, t.bounds_m.min_y - m.max_y);
    }
    const double f = ds.frame.xy_to_metres;
    const double cx = m.max_x + (std::isfinite(gap_x) ? gap_x / 2 : 0);
    const double cy = m.max_y + (std::isfinite(gap_y) ? gap_y / 2 : 0);
    const double a = std::numbers::pi / 6, h = 500.0;
    Ring ring;
    for (const auto& [u, v] : {std::pair{-h, -h}, {h, -h}, {h, h}, {-h, h}}) {
        ring.push_back({(cx + u * std::cos(a) - v * std::sin(a)) / f, (cy + u * std::sin(a) + v * std::cos(a)) / f});
    }
    return MultiPolygon({{ring}});
}

struct Records {
    std::uint64_t count = 0;
    std::string sha;
};

// Every record of the file at `path` (one tile), hashed in file order.
Records file_records(const std::string& path, ThreadPool& pool) {
    const dataset::Dataset out = dataset::open_dataset({path});
    dataset::require_tiles(out, "bench_region");
    const auto& tile = out.tiles[0].tile;
    Sha256 sha;
    Records r;
    dataset::for_each_record_batch(io::File::open(tile.path()), tile, pool,
                                   [&](std::uint64_t, std::span<const std::uint8_t> records) {
                                       sha.update(records);
                                       r.count += records.size() / tile.header.record_length;
                                   });
    r.sha = sha.hex_digest();
    return r;
}

// The brute force: each touched tile decoded on its own, every point tested against the polygon (in the
// file's coordinates: the replica's tiles share one CRS and unit), kept records re-quantized to the
// output header's scale and offset, hashed in tile and file order.
Records brute_force(const dataset::Dataset& ds, std::span<const std::uint32_t> tiles, const MultiPolygon& polygon,
                    const las::Header& out, ThreadPool& pool) {
    Sha256 sha;
    Records r;
    std::vector<std::uint8_t> kept;
    for (const auto t : tiles) {
        const auto& dt = ds.tiles[t];
        if (dt.to_frame || dt.xy_to_metres != ds.frame.xy_to_metres) {
            throw Error(dt.tile.path(), std::nullopt, "the brute force expects every tile in the frame's CRS and unit");
        }
        const auto& h = dt.tile.header;
        const auto& format = las::point_format_info(h.point_format);
        dataset::for_each_record_batch(
            io::File::open(dt.tile.path()), dt.tile, pool, [&](std::uint64_t, std::span<const std::uint8_t> records) {
                kept.clear();
                for (std::size_t at = 0; at + h.record_length <= records.size(); at += h.record_length) {
                    const auto record = records.subspan(at, h.record_length);
                    const las::Point p = las::decode_point(record, format, h);
                    if (!polygon.contains(p.x, p.y)) continue;
                    const std::size_t k = kept.size();
                    kept.insert(kept.end(), record.begin(), record.end());
                    const double v[3] = {p.x, p.y, p.z};
                    for (int a = 0; a < 3; ++a) {
                        const auto raw = static_cast<std::int32_t>(std::llround((v[a] - out.offset[a]) / out.scale[a]));
                        std::memcpy(kept.data() + k + 4 * a, &raw, 4);
                    }
                    ++r.count;
                }
                sha.update(kept);
            });
    }
    r.sha = sha.hex_digest();
    return r;
}

nlohmann::json bench_clip(const Options& o, ThreadPool& pool) {
    const auto t0 = bench::Clock::now();
    const dataset::Dataset ds = dataset::open_dataset({o.replica});
    dataset::require_tiles(ds, "bench_region");
    const double open_seconds = bench::seconds_since(t0);
    const MultiPolygon polygon = clip_square(ds);
    const pipelines::Region region = pipelines::polygon_region(polygon);
    std::size_t box_touching = 0;
    const pipelines::Region box = pipelines::box_region(polygon.min_x(), polygon.min_y(), polygon.max_x(),
                                                        polygon.max_y());
    box_touching = pipelines::tiles_touching(ds, box).size();
    fs::path temp;
    pipelines::ClipRequest request;
    request.region = region;
    request.output = o.out;
    if (o.out.empty()) {
        temp = fs::temp_directory_path() / ("lidarscout_bench_region_" + std::to_string(::getpid()));
        fs::create_directories(temp);
        request.output = (temp / "clip.laz").string();
    }
    std::vector<double> seconds, cpu;
    pipelines::ClipResult r = pipelines::clip_to_file(ds, request, pool);  // warms the page cache
    for (int k = 0; k < o.runs; ++k) {
        const auto t = bench::Clock::now();
        const double cpu0 = cpu_seconds();
        r = pipelines::clip_to_file(ds, request, pool);
        seconds.push_back(bench::seconds_since(t));
        cpu.push_back(cpu_seconds() - cpu0);
    }
    const Records written = file_records(request.output, pool);
    const las::Header out = dataset::open_dataset({request.output}).tiles.at(0).tile.header;
    const Records expected = brute_force(ds, r.read.tiles_touched, polygon, out, pool);
    if (!temp.empty()) fs::remove_all(temp);
    const double f = ds.frame.xy_to_metres;
    return {{"dataset", o.replica},
            {"tiles", ds.tiles.size()},
            {"open_seconds", open_seconds},
            {"area_km2", polygon.area() * f * f / 1e6},
            {"output", o.out.empty() ? "(temporary)" : o.out},
            {"tiles_touching_box", box_touching},
            {"tiles_touching", r.read.tiles_touched.size()},
            {"tiles_decoded", r.read.tiles_decoded},
            {"points_read", r.read.points_read},
            {"points_written", r.points_written},
            {"bytes_written", r.bytes_written},
            {"seconds", median(seconds)},
            {"cpu_seconds", median(cpu)},
            {"runs", o.runs},
            {"points_sha256", written.sha},
            {"brute_force_points", expected.count},
            {"brute_force_sha256", expected.sha},
            {"match", written.count == r.points_written && written.count == expected.count &&
                          written.sha == expected.sha}};
}

void print_text(const nlohmann::json& p, const nlohmann::json& c) {
    const auto l = p["line"];
    fmt::print("profile: {} ({} tiles, opened in {:.3f} s), line ({:.2f}, {:.2f}) - ({:.2f}, {:.2f}) in {}\n",
               p["dataset"].get<std::string>(), p["tiles"].get<std::size_t>(), p["open_seconds"].get<double>(),
               l[0].get<double>(), l[1].get<double>(), l[2].get<double>(), l[3].get<double>(),
               p["crs"].get<std::string>());
    fmt::print("  length {:.1f} m, width {:.1f} m: {} points ({} read), {} tiles touched, {} decoded\n",
               p["length_m"].get<double>(), p["width_m"].get<double>(), p["points"].get<std::size_t>(),
               p["points_read"].get<std::uint64_t>(), p["tiles_touched"].get<std::size_t>(),
               p["tiles_decoded"].get<std::uint64_t>());
    fmt::print("  first points {:.3f} s (target 0.5 s), complete {:.3f} s (target 5 s), {:.2f} CPU s; medians of {} "
               "runs\n", p["seconds_to_first_points"].get<double>(), p["seconds"].get<double>(),
               p["cpu_seconds"].get<double>(), p["runs"].get<int>());
    fmt::print("clip: {} ({} tiles, opened in {:.3f} s), a {:.3f} km² square turned 30 degrees -> {}\n",
               c["dataset"].get<std::string>(), c["tiles"].get<std::size_t>(), c["open_seconds"].get<double>(),
               c["area_km2"].get<double>(), c["output"].get<std::string>());
    fmt::print("  tiles touching its box {}, touching it {}, decoded {}; {} points read, {} written ({} bytes)\n",
               c["tiles_touching_box"].get<std::size_t>(), c["tiles_touching"].get<std::size_t>(),
               c["tiles_decoded"].get<std::uint64_t>(), c["points_read"].get<std::uint64_t>(),
               c["points_written"].get<std::uint64_t>(), c["bytes_written"].get<std::uint64_t>());
    fmt::print("  {:.3f} s, {:.2f} CPU s, medians of {} runs\n", c["seconds"].get<double>(),
               c["cpu_seconds"].get<double>(), c["runs"].get<int>());
    fmt::print("  output records sha256 {}\n  brute force: {} points, sha256 {}\n  match: {}\n",
               c["points_sha256"].get<std::string>(), c["brute_force_points"].get<std::uint64_t>(),
               c["brute_force_sha256"].get<std::string>(), c["match"].get<bool>() ? "yes" : "no");
}

int run(int argc, char** argv) {
    Options o;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--survey" && i + 1 < argc) o.survey = argv[++i];
        else if (a == "--replica" && i + 1 < argc) o.replica = argv[++i];
        else if (a == "--out" && i + 1 < argc) o.out = argv[++i];
        else if (a == "--runs" && i + 1 < argc) o.runs = std::max(1, std::stoi(argv[++i]));
        else if (a == "--threads" && i + 1 < argc) o.threads = std::max(1, std::stoi(argv[++i]));
        else if (a == "--json") o.json = true;
        else throw Error::in_stage("bench_region", "unknown argument '" + a + "'; see --help");
    }
    ThreadPool pool(static_cast<unsigned>(o.threads));
    const nlohmann::json profile = bench_profile(o, pool);
    const nlohmann::json clip = bench_clip(o, pool);
    if (o.json) {
        fmt::print("{}\n", nlohmann::json{{"threads", o.threads}, {"profile", profile}, {"clip", clip}}.dump(2));
    } else {
        print_text(profile, clip);
    }
    return clip["match"].get<bool>() ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
    return lidarscout::bench::bench_main(
        "bench_region", "[--survey PATH] [--replica PATH] [--runs N] [--threads N] [--out FILE.laz] [--json]", argc,
        argv, run);
}
