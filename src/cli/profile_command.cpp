// `lidarscout profile PATH... --line x0,y0,x1,y1 [--width W] -o OUT.csv|.laz|.las|.png [--exaggeration F]
// [--classes ..] [--returns ..] [--intensity ..] [--crs EPSG:n] [--threads N] [--force] [--json]`: every point
// at full resolution in a corridor along a line (pipelines/profile.hpp), as CSV, as LAS/LAZ (as clip
// writes them) or as an image of distance against height coloured by class.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdio>
#include <memory>
#include <thread>

#include "cli/commands.hpp"
#include "cli/json_output.hpp"
#include "cli/filter_options.hpp"
#include "cli/io_options.hpp"
#include "cli/number_options.hpp"
#include "cli/region_options.hpp"
#include "cli/thread_options.hpp"
#include "core/error.hpp"
#include "core/thread_pool.hpp"
#include "pipelines/clip.hpp"
#include "pipelines/profile.hpp"
#include "pipelines/profile_image.hpp"
#include "render/png_writer.hpp"

namespace lidarscout::cli {
namespace {

struct ProfileCliOptions {
    std::vector<std::string> paths;
    std::string output, crs;
    std::vector<double> line;
    double width = 2, exaggeration = 1;
    FilterTexts filter;
    unsigned threads = 0;
    bool force = false;
    bool json = false;
};

std::string extension(const std::string& path) {
    const auto dot = path.rfind('.');
    std::string ext = dot == std::string::npos ? "" : path.substr(dot);
    for (auto& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return ext;
}

pipelines::Corridor corridor(const ProfileCliOptions& o) {
    return {o.line[0], o.line[1], o.line[2], o.line[3], o.width};
}

// LAS/LAZ: the corridor clipped as `clip` writes it.
nlohmann::json write_points(const ProfileCliOptions& o, const dataset::Dataset& ds, ThreadPool& pool, int& status) {
    pipelines::ClipRequest request;
    request.output = o.output;
    request.filter = o.filter.filter();
    request.region = pipelines::corridor_region(corridor(o));
    request.command = "profile";
    request.where = pipelines::kCorridor;
    request.force = o.force;
    PointsBar bar("profile");
    request.watch.progress = bar.fn();
    const auto r = pipelines::clip_to_file(ds, request, pool);
    for (const auto& n : r.notes) std::fprintf(stderr, "lidarscout: note: %s\n", n.c_str());
    status = report_skips(r.read, ds);
    nlohmann::json j = region_stats_json(r.read, ds);
    j["points_written"] = r.points_written;
    return j;
}

// CSV or PNG from the points read.
nlohmann::json write_profile(const ProfileCliOptions& o, const dataset::Dataset& ds, ThreadPool& pool, int& status) {
    PointsBar bar("profile");
    pipelines::ReadWatch watch;
    watch.progress = bar.fn();
    const pipelines::Profile p = pipelines::read_profile(ds, corridor(o), o.filter.filter(), pool, watch);
    pipelines::require_profile_points(ds, corridor(o), o.filter.filter(), p, pool);  // nothing written when empty
    nlohmann::json j = region_stats_json(p.read, ds);
    if (extension(o.output) == ".png") {
        pipelines::ProfileImageScale s;
        const auto image = pipelines::profile_image(p, corridor(o), pipelines::profile_png_options(ds.frame,
                                                                                                   o.exaggeration), &s);
        render::write_png(o.output, image);
        j["image"] = {{"width", image.width}, {"height", image.height}, {"z_min", s.z_min}, {"z_max", s.z_max},
                      {"distance_grid_step", s.distance_step}, {"z_grid_step", s.z_step},
                      {"exaggeration", s.exaggeration}};
    } else {
        pipelines::write_profile_csv(o.output, ds, p);
    }
    status = report_skips(p.read, ds);
    j["points_written"] = p.points.size();
    j["seconds_to_first_points"] = p.seconds_to_first_points;
    return j;
}

int run_profile(const ProfileCliOptions& o) {
    const auto t0 = std::chrono::steady_clock::now();
    o.filter.filter();  // option errors before any work
    const std::string ext = extension(o.output);
    const dataset::Dataset ds =
        open_region_dataset(o.paths, o.crs, "profile", false, {}, pipelines::corridor_region(corridor(o)).touches);
    ThreadPool pool(o.threads ? o.threads : std::max(1u, std::thread::hardware_concurrency()));
    int status = 0;
    nlohmann::json j = ext == ".laz" || ext == ".las" ? write_points(o, ds, pool, status)
                                                      : write_profile(o, ds, pool, status);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    j["output"] = o.output;
    j["length"] = corridor(o).length();
    j["width"] = o.width;
    j["seconds"] = seconds;
    if (o.json) {
        print_json_answer(j);
    } else {
        std::printf("%s: %llu points in a corridor %g long and %g wide, %zu tiles touched, %llu decoded, %.2f s\n",
                    o.output.c_str(), j["points_written"].get<unsigned long long>(), corridor(o).length(), o.width,
                    j["tiles_touched"].get<std::size_t>(), j["tiles_decoded"].get<unsigned long long>(), seconds);
    }
    return status;
}

}  // namespace

void register_profile_command(CLI::App& app, std::function<int()>& run) {
    auto o = std::make_shared<ProfileCliOptions>();
    auto* cmd = app.add_subcommand(
        "profile", "Write every point in a corridor along a line: CSV, LAS/LAZ, or a PNG of distance against height");
    add_inputs(*cmd, "paths", o->paths, "LAS/LAZ files, folders (searched recursively) or text files listing tiles")
        ->required();
    add_output(*cmd, "-o,--output", o->output,
               "The profile: .csv (distance,x,y,z,class,intensity,return,returns,source_file), .laz/.las (the points "
               "as clip writes them) or .png (distance against height at true scale, coloured by class, ground on "
               "top, labelled axes)",
               io::OutputKind::Profile)
        ->required();
    cmd->add_option("--line", o->line, "x0,y0,x1,y1: the line, in the CRS's units")
        ->delimiter(',')->expected(4)->required();
    cmd->add_option("--width", o->width, "The corridor's full width, in the CRS's units (default 2)")
        ->check(positive_number());
    cmd->add_option("--exaggeration", o->exaggeration,
                    "The PNG's vertical scale over its horizontal one (default 1: true scale)")
        ->check(positive_number());
    add_filter_options(*cmd, o->filter, "points in the profile");
    cmd->add_option("--crs", o->crs, "The dataset's CRS, e.g. EPSG:32616 (default: the CRS most tiles use)");
    add_thread_option(*cmd, "--threads", o->threads, "Threads for decoding (default: all cores)");
    add_force_flag(*cmd, o->force);
    cmd->add_flag("--json", o->json,
                  "Print the result as JSON (tiles_touched, tiles_decoded, points_read, points_written, skipped, "
                  "seconds_to_first_points)");
    cmd->callback([o, &run] { run = [o] { return run_profile(*o); }; });
}

}  // namespace lidarscout::cli
