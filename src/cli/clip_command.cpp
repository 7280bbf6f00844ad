// `lidarscout clip PATH... (--bounds xmin,ymin,xmax,ymax | --polygon FILE.geojson|WKT) -o OUT.laz|.las
// [--classes ..] [--returns ..] [--intensity ..] [--crs EPSG:n] [--threads N] [--force] [--json]`: the
// points of a dataset inside an area, as one LAS/LAZ file (pipelines/clip.hpp).
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <system_error>
#include <thread>

#include "cli/commands.hpp"
#include "cli/json_output.hpp"
#include "cli/filter_options.hpp"
#include "cli/io_options.hpp"
#include "cli/region_options.hpp"
#include "cli/thread_options.hpp"
#include "core/error.hpp"
#include "core/thread_pool.hpp"
#include "core/polygon.hpp"
#include "core/polygon_validity.hpp"
#include "core/text.hpp"
#include "pipelines/clip.hpp"

namespace lidarscout::cli {
namespace {

struct ClipCliOptions {
    std::vector<std::string> paths;
    std::string output, polygon, crs;
    std::vector<double> bounds;
    FilterTexts filter;
    unsigned threads = 0;
    bool force = false;
    bool json = false;
};

// The --polygon argument's polygon; a warning when its edges cross (or when that could not be checked).
MultiPolygon clip_polygon(const std::string& argument) {
    MultiPolygon polygon = read_polygon_argument(argument);
    std::error_code ec;
    const std::string name = std::filesystem::is_regular_file(argument, ec) ? argument : "the --polygon WKT";
    const std::string warning = crossing_warning(find_crossing(polygon), name);
    if (!warning.empty()) std::fprintf(stderr, "lidarscout: warning: %s\n", display_text(warning).c_str());
    return polygon;
}

pipelines::Region clip_region(const ClipCliOptions& o) {
    if (o.bounds.empty() == o.polygon.empty()) throw Error("clip: give either --bounds or --polygon");
    if (!o.polygon.empty()) return pipelines::polygon_region(clip_polygon(o.polygon));
    return pipelines::bounds_region(o.bounds, "clip", "--bounds");
}

void print_result(const ClipCliOptions& o, const dataset::Dataset& ds, const pipelines::ClipResult& r,
                  double seconds) {
    for (const auto& n : r.notes) std::fprintf(stderr, "lidarscout: note: %s\n", n.c_str());
    if (o.json) {
        nlohmann::json j = region_stats_json(r.read, ds);
        j["output"] = o.output;
        j["points_written"] = r.points_written;
        j["bytes"] = r.bytes_written;
        j["notes"] = r.notes;
        j["seconds"] = seconds;
        print_json_answer(j);
        return;
    }
    std::printf("%s: %llu points written of %llu read, %zu tiles touched, %llu decoded, %.2f s\n", o.output.c_str(),
                (unsigned long long)r.points_written, (unsigned long long)r.read.points_read,
                r.read.tiles_touched.size(), (unsigned long long)r.read.tiles_decoded, seconds);
}

int run_clip(const ClipCliOptions& o) {
    const auto t0 = std::chrono::steady_clock::now();
    pipelines::ClipRequest request;
    request.filter = o.filter.filter();
    request.output = o.output;
    request.force = o.force;
    request.region = clip_region(o);  // (option errors before any work)
    const dataset::Dataset ds = open_region_dataset(o.paths, o.crs, "clip", true, {}, request.region.touches);
    PointsBar bar("clip");
    request.watch.progress = bar.fn();
    ThreadPool pool(o.threads ? o.threads : std::max(1u, std::thread::hardware_concurrency()));
    const pipelines::ClipResult r = pipelines::clip_to_file(ds, request, pool);
    const int status = report_skips(r.read, ds);
    print_result(o, ds, r, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    return status;
}

}  // namespace

void register_clip_command(CLI::App& app, std::function<int()>& run) {
    auto o = std::make_shared<ClipCliOptions>();
    auto* cmd = app.add_subcommand(
        "clip", "Write the points inside a box or polygon as one LAS/LAZ file (point format, header, VLRs kept)");
    add_inputs(*cmd, "paths", o->paths, "LAS/LAZ files, folders (searched recursively) or text files listing tiles")
        ->required();
    add_output(*cmd, "-o,--output", o->output, "The .laz or .las to write (through a temporary name)",
               io::OutputKind::PointCloud)
        ->required();
    cmd->add_option("--bounds", o->bounds,
                    "xmin,ymin,xmax,ymax in the CRS's units (degrees for data in longitude/latitude; edges inside)")
        ->delimiter(',')->expected(4);
    cmd->add_option("--polygon", o->polygon,
                    "A GeoJSON file (Polygon, MultiPolygon, Feature(Collection)) or WKT 'POLYGON ((x y, ...))' / "
                    "'MULTIPOLYGON (...)', in the CRS's units; holes cut out, edges inside");
    add_filter_options(*cmd, o->filter, "points clipped");
    cmd->add_option("--crs", o->crs,
                    "The dataset's CRS, e.g. EPSG:32616 (default: the CRS most tiles use); tiles in another CRS are "
                    "reprojected into it (tiles in degrees too) and the output is then written in it");
    add_thread_option(*cmd, "--threads", o->threads, "Threads for decoding and encoding (default: all cores)");
    add_force_flag(*cmd, o->force);
    cmd->add_flag("--json", o->json,
                  "Print the result as JSON (tiles_touched, tiles_decoded, points_read, points_written, skipped)");
    cmd->callback([o, &run] { run = [o] { return run_clip(*o); }; });
}

}  // namespace lidarscout::cli
