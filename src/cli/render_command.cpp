// `lidarscout render PATH... --camera X,Y,Z,YAW,PITCH|auto --size WxH --until overview|heightmaps|full
// -o out.png`: renders, without a window, what the viewer shows at a camera once a stage is
// complete for the visible region: the chunk points (overview), plus the patches' heightmaps
// (linear or the network), plus the full-resolution points of the tiles in view within a memory
// budget, laid over the heightmaps as the viewer does (the surface under real points at their
// height: the heightmap shows only where points are missing). Prints a one-line summary (or
// JSON) with the time per stage.
#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <charconv>
#include <chrono>
#include <filesystem>
#include <cstdio>
#include <memory>
#include <tuple>
#include <optional>
#include <thread>

#include "cli/commands.hpp"
#include "cli/json_output.hpp"
#include "cli/number_options.hpp"
#include "cli/io_options.hpp"
#include "cli/diagnostic_output.hpp"
#include "cli/filter_options.hpp"
#include "cli/stage_progress.hpp"
#include "cli/progress.hpp"
#include "cli/size_options.hpp"
#include "cli/thread_options.hpp"
#include "core/error.hpp"
#include "dataset/chunk_point_loader.hpp"
#include "dataset/dataset.hpp"
#include "core/patch_grid.hpp"
#include "nn/heightmap_network.hpp"
#include "render/backend.hpp"
#include "raster/dem_grid.hpp"
#include "render/camera.hpp"
#include "render/png_writer.hpp"
#include "viewer/heightmap_builder.hpp"
#include "viewer/scene.hpp"
#include "viewer/scheduler.hpp"
#include "viewer/patch_detail.hpp"
#include "viewer/visibility.hpp"

namespace lidarscout::cli {
namespace {

enum class Stage { Overview, Heightmaps, Full };

struct RenderCliOptions {
    std::vector<std::string> paths;
    FilterTexts filter;  // the points drawn (a ground filter also makes the heightmaps bare earth)
    std::string camera = "auto";
    double fov = 60;
    std::string size = "1280x720";
    std::string until = "full";
    std::string output;
    std::string colour = "rgb";
    std::string heightmaps = "linear";
    std::string model;
    std::string crs;
    int point_size = 1;
    bool fixed_point_size = false;
    int chunk_point_size = 2;
    float edl = 0;
    std::size_t min_points = viewer::kViewerMinPoints;
    std::string memory;
    unsigned threads = 0;
    std::string backend = "cpu";
    bool json = false;
};

// The options checked and parsed (everything that can be wrong before any file is read).
struct RenderPlan {
    int width = 0, height = 0;
    Stage until = Stage::Full;
    render::ColourMode colour = render::ColourMode::Rgb;
    bool cnn = false;
    std::string model_path;          // cnn only
    std::optional<render::Camera> camera;  // empty: auto
    std::uint64_t memory_budget = 0;
    unsigned threads = 1;
    render::BackendChoice backend;   // resolved: cpu or cuda (with a note when auto fell back)
    PointFilter filter;              // the points drawn
};

struct StageTimes {
    double headers = 0, chunk_points = 0, heightmaps = 0, full_res = 0, render = 0;
};

struct RenderReport {
    std::size_t tiles = 0, skipped = 0, patches = 0, visible_patches = 0;
    std::uint64_t chunk_points = 0, chunk_points_drawn = 0, full_res_points = 0;
    std::size_t heightmaps = 0, full_res_tiles = 0, full_res_over_budget = 0, drawn_pixels = 0;
    bool has_rgb = false;  // the survey has colour (chunk_points_have_rgb)
    std::size_t chunk_point_errors = 0;    // chunk points not read (each also a warning)
    std::vector<ErrorRecord> skipped_data;  // full-resolution chunks or tiles left out (undecodable)
    std::uint64_t points_skipped = 0;
    Diagnostics warnings;
    dataset::Frame frame;  // the CRS units the camera is shown in
    render::Camera camera;
    StageTimes seconds;
};

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

const char* stage_name(Stage s) {
    return s == Stage::Overview ? "overview" : s == Stage::Heightmaps ? "heightmaps" : "full";
}

Stage parse_stage(const std::string& text) {
    for (Stage s : {Stage::Overview, Stage::Heightmaps, Stage::Full}) {
        if (text == stage_name(s)) return s;
    }
    throw Error("unknown --until '" + text + "' (overview, heightmaps or full)");
}

// A --memory value; empty = a quarter of the RAM (the viewer's default budget).
std::uint64_t parse_memory(const std::string& text) {
    return text.empty() ? viewer::default_memory_budget() : parse_bytes(text);
}

RenderPlan make_plan(const RenderCliOptions& o) {
    RenderPlan plan;
    std::tie(plan.width, plan.height) = parse_pixels(o.size, 1);
    plan.until = parse_stage(o.until);
    plan.colour = render::parse_colour_mode(o.colour);
    plan.filter = o.filter.filter();
    if (o.heightmaps != "linear" && o.heightmaps != "cnn") {
        throw Error("unknown --heightmaps '" + o.heightmaps + "' (linear or cnn)");
    }
    if (!(o.fov > 0 && o.fov < 180)) throw Error("bad --fov: the field of view must be within (0, 180) degrees");
    if (o.camera != "auto") plan.camera = render::parse_camera(o.camera, plan.width, plan.height, o.fov);
    plan.cnn = o.heightmaps == "cnn" && plan.until != Stage::Overview;
    if (plan.cnn) plan.model_path = o.model.empty() ? nn::default_model_path() : o.model;
    if (plan.cnn && !std::filesystem::is_regular_file(plan.model_path)) {
        throw Error(plan.model_path + ": no such heightmap network model file");
    }
    plan.memory_budget = parse_memory(o.memory);
    plan.threads = o.threads ? o.threads : std::max(1u, std::thread::hardware_concurrency());
    plan.backend = render::choose_backend(render::parse_backend(o.backend));  // throws for an unavailable cuda
    return plan;
}

dataset::Dataset read_headers(const RenderCliOptions& o, RenderReport& report) {
    const auto t0 = Clock::now();
    dataset::DatasetOptions dataset_options;
    dataset_options.crs = o.crs;
    auto ds = open_with_progress(o.paths, dataset_options);
    for (const auto& s : ds.skipped) std::fprintf(stderr, "lidarscout: skipped %s\n", s.error.c_str());
    dataset::require_tiles(ds, "render");
    report.tiles = ds.tiles.size();
    report.skipped = ds.skipped.size();
    report.warnings = ds.warnings;
    report.seconds.headers = seconds_since(t0);
    return ds;
}

// --camera is in the CRS's units, as --bounds and the coordinates `info` prints: x, y in the horizontal
// unit, z in the vertical one; the camera itself works in metres.
render::Camera make_camera(const RenderPlan& plan, const RenderCliOptions& o, const dataset::Dataset& ds) {
    if (plan.camera) {
        render::Camera c = *plan.camera;
        c.x *= ds.frame.xy_to_metres, c.y *= ds.frame.xy_to_metres, c.z *= ds.frame.z_to_metres;
        return c;
    }
    const auto& b = ds.bounds_m;
    return render::Camera::looking_at_bounds(b.min_x, b.min_y, b.min_z, b.max_x, b.max_y, b.max_z, plan.width,
                                             plan.height, o.fov);
}

void load_chunk_points(const dataset::Dataset& ds, lidarscout::PatchGrid& grid, const render::Camera& camera,
                       RenderReport& report) {
    const auto t0 = Clock::now();
    dataset::ChunkPointLoader loader(ds, grid);
    loader.set_focus(camera.x, camera.y);
    load_with_progress(loader);
    for (const auto& e : loader.errors()) {
        report.warnings.add({DiagnosticLevel::warning, e.file, e.offset, e.message()});
    }
    if (loader.loaded() == 0 && loader.failed() > 0) {
        const std::string first = loader.errors().empty() ? std::string() : ": " + loader.errors().front().message();
        throw Error::in_stage("render", "every chunk point failed (" + std::to_string(loader.failed()) + ")" + first);
    }
    report.chunk_point_errors = loader.errors().size();
    grid.shrink_to_fit();
    report.chunk_points = loader.loaded();
    report.has_rgb = viewer::chunk_points_have_rgb(grid);
    report.patches = grid.cells().size();
    report.seconds.chunk_points = seconds_since(t0);
}

std::vector<viewer::PatchHeightmap> build_heightmaps(const RenderPlan& plan, const RenderCliOptions& o,
                                                     const dataset::Dataset& ds, const lidarscout::PatchGrid& grid,
                                                     std::span<const lidarscout::CellKey> cells, ThreadPool& pool,
                                                     RenderReport& report) {
    const auto t0 = Clock::now();
    viewer::HeightmapBuildOptions opt;
    opt.patch.min_points = o.min_points;
    opt.patch.has_rgb = report.has_rgb;
    opt.footprints = viewer::tile_footprints(ds);
    Progress progress("heightmaps", cells.size());
    opt.progress = [&](std::size_t n) { progress.add(n); };
    std::vector<viewer::PatchHeightmap> out;
    if (plan.cnn) {
        const auto network = nn::HeightmapNetwork::load(plan.model_path, static_cast<int>(plan.threads));
        out = viewer::build_cnn_heightmaps(grid, cells, network, opt, pool);
    } else {
        out = viewer::build_linear_heightmaps(grid, cells, opt, pool);
    }
    progress.finish();
    report.heightmaps = out.size();
    report.seconds.heightmaps = seconds_since(t0);
    return out;
}

std::vector<viewer::PointSet> decode_full_res(const RenderPlan& plan, const dataset::Dataset& ds,
                                              const render::Camera& camera, ThreadPool& pool, RenderReport& report) {
    const auto t0 = Clock::now();
    viewer::FullResOptions opt;
    opt.memory_budget = plan.memory_budget;
    opt.few_tiles = ds.tiles.size();  // every tile in view (as the viewer ends), nearest first, while it fits
    const auto choice = viewer::choose_full_res_tiles(ds, camera, opt);
    std::uint64_t total = 0;
    for (const auto i : choice.tiles) total += ds.tiles[i].tile.header.point_count;
    Progress progress("full-res points", total);
    std::vector<viewer::PointSet> out;
    std::vector<dataset::SkippedChunk> skipped;
    for (const auto i : choice.tiles) {
        try {  // a corrupt chunk costs its points, a tile that cannot be opened its own
            out.push_back(viewer::tile_point_set(ds.tiles[i], ds.las_stride, pool,
                                                 [&](std::uint64_t n) { progress.add(n); }, &skipped,
                                                 &plan.filter));
        } catch (const Error& e) {
            skipped.push_back({0, ds.tiles[i].tile.header.point_count, ErrorRecord::of(e)});
        }
    }
    progress.finish();
    for (const auto& s : skipped) {
        report.skipped_data.push_back(s.error);
        report.points_skipped += s.points;
    }
    report.full_res_tiles = out.size();
    report.full_res_over_budget = choice.over_budget;
    report.full_res_points = viewer::point_count(out);
    report.seconds.full_res = seconds_since(t0);
    return out;
}

viewer::SceneStyle scene_style(const RenderPlan& plan, const RenderCliOptions& o, const dataset::Dataset& ds) {
    viewer::SceneStyle style;
    style.colour = viewer::colour_settings(plan.colour, ds.bounds_m.min_z, ds.bounds_m.max_z);
    style.point_size = o.point_size;
    style.adaptive_point_size = !o.fixed_point_size;
    style.chunk_point_size = o.chunk_point_size;
    style.resolve.edl_strength = o.edl;
    style.backend = plan.backend.backend;
    style.filter = plan.filter;
    return style;
}

// The camera as --camera takes it: x, y, z in the CRS's units (and its position in metres, as the
// viewer's camera has it).
nlohmann::json camera_json(const render::Camera& c, const dataset::Frame& f) {
    const double x = c.x / f.xy_to_metres, y = c.y / f.xy_to_metres, z = c.z / f.z_to_metres;
    return {{"x", x}, {"y", y}, {"z", z}, {"position_m", {c.x, c.y, c.z}}, {"yaw_deg", c.yaw_deg},
            {"pitch_deg", c.pitch_deg},
            {"fov_deg", c.fov_deg}, {"near_m", c.near_m}, {"far_m", c.far_m},
            {"text", fmt::format("{:.2f},{:.2f},{:.2f},{:g},{:g}", x, y, z, c.yaw_deg, c.pitch_deg)}};
}

// An image without any of the data is an error with the reason, not a blank PNG.
void check_something_drawn(const viewer::RenderedScene& frame, const render::Camera& c, const dataset::Dataset& ds) {
    if (frame.drawn_pixels > 0) return;
    const double f = ds.frame.xy_to_metres;
    const auto& b = ds.bounds_m;
    const std::string unit = raster::linear_unit_name(f);
    throw Error::in_stage("render", fmt::format("the camera at {:.2f},{:.2f} sees none of the data, which lies in "
                                                "{:.2f},{:.2f},{:.2f},{:.2f} (xmin,ymin,xmax,ymax in the CRS's units{}"
                                                "{}; --camera takes the same units); nothing written",
                                                c.x / f, c.y / f, b.min_x / f, b.min_y / f, b.max_x / f, b.max_y / f,
                                                unit.empty() ? "" : ": ", unit));
}

void print_json(const RenderCliOptions& o, const RenderPlan& plan, const RenderReport& r) {
    const auto& s = r.seconds;
    nlohmann::json j = {{"output", o.output},
                        {"width", plan.width},
                        {"height", plan.height},
                        {"until", stage_name(plan.until)},
                        {"colour", render::colour_mode_name(plan.colour)},
                        {"points_drawn", plan.filter.describe()},
                        {"heightmap_method", plan.cnn ? "cnn" : "linear"},
                        {"backend", std::string(render::backend_name(plan.backend.backend))},
                        {"camera", camera_json(r.camera, r.frame)},
                        {"tiles", r.tiles},
                        {"has_rgb", r.has_rgb},
                        {"skipped", r.skipped},
                        {"chunk_points", r.chunk_points},
                        {"patches", r.patches},
                        {"visible_patches", r.visible_patches},
                        {"patches_with_heightmaps", r.heightmaps},
                        {"chunk_points_drawn", r.chunk_points_drawn},
                        {"full_res_tiles", r.full_res_tiles},
                        {"full_res_tiles_over_budget", r.full_res_over_budget},
                        {"full_res_points", r.full_res_points},
                        {"points_skipped", r.points_skipped},
                        {"skipped_chunks", skipped_json(r.skipped_data)},
                        {"memory_budget", plan.memory_budget},
                        {"drawn_pixels", r.drawn_pixels},
                        {"warnings", r.warnings.messages()},
                        {"diagnostics", diagnostics_json(r.warnings)},
                        {"seconds", {{"headers", s.headers}, {"chunk_points", s.chunk_points},
                                     {"heightmaps", s.heightmaps}, {"full_res", s.full_res}, {"render", s.render}}}};
    if (plan.cnn) j["model"] = plan.model_path;
    print_json_answer(j);
}

void print_summary(const RenderCliOptions& o, const RenderPlan& plan, const RenderReport& r) {
    print_diagnostics(r.warnings);
    const auto& s = r.seconds;
    const std::string budget =
        r.full_res_over_budget ? fmt::format(", {} over the memory budget", r.full_res_over_budget) : "";
    std::fprintf(stderr,
                 "render: %zu tiles, %llu chunk points, %zu of %zu visible patches with heightmaps (%s), %llu full-res "
                 "points from %zu tiles%s; headers %.3f s, chunk points %.3f s, heightmaps %.3f s, full-res %.3f s, "
                 "render %.3f s -> %s (camera %s)\n",
                 r.tiles, (unsigned long long)r.chunk_points, r.heightmaps, r.visible_patches,
                 plan.cnn ? "cnn" : "linear", (unsigned long long)r.full_res_points, r.full_res_tiles, budget.c_str(),
                 s.headers, s.chunk_points, s.heightmaps, s.full_res, s.render, o.output.c_str(),
                 camera_json(r.camera, r.frame)["text"].get<std::string>().c_str());
}

int run_render(const RenderCliOptions& o) {
    const RenderPlan plan = make_plan(o);
    if (!plan.backend.note.empty()) {
        std::fprintf(stderr, "lidarscout: %s; drawing on the CPU\n", plan.backend.note.c_str());
    }
    RenderReport report;
    const dataset::Dataset ds = read_headers(o, report);
    report.camera = make_camera(plan, o, ds);
    report.frame = ds.frame;
    const auto [ox, oy] = dataset::patch_grid_origin(ds);
    lidarscout::PatchGrid grid(ox, oy);
    load_chunk_points(ds, grid, report.camera, report);
    ThreadPool pool(plan.threads);
    const auto cells = viewer::visible_cells(grid, report.camera, ds.bounds_m.min_z, ds.bounds_m.max_z);
    report.visible_patches = cells.size();
    viewer::Scene scene;
    if (plan.until != Stage::Overview) scene.heightmaps = build_heightmaps(plan, o, ds, grid, cells, pool, report);
    scene.chunk_points = viewer::overview_point_sets(grid, cells, scene.heightmaps);
    report.chunk_points_drawn = viewer::point_count(scene.chunk_points);
    if (plan.until == Stage::Full) scene.full_points = decode_full_res(plan, ds, report.camera, pool, report);
    if (!report.has_rgb) {
        viewer::paint_uncoloured(scene.chunk_points);
        viewer::paint_uncoloured(scene.full_points);
    }
    // As the viewer, once the tiles are in (a ground filter: bare earth where they fell, the rest tinted).
    viewer::overlay_points(scene.heightmaps, scene.full_points, grid, viewer::surface_of(plan.filter));
    const auto t0 = Clock::now();
    const auto frame = viewer::render_scene(scene, report.camera, scene_style(plan, o, ds), pool);
    check_something_drawn(frame, report.camera, ds);
    render::write_png(o.output, frame.image);
    report.drawn_pixels = frame.drawn_pixels;
    report.seconds.render = seconds_since(t0);
    print_skipped(report.skipped_data);
    if (o.json) print_json(o, plan, report);
    else print_summary(o, plan, report);
    return written_exit_status(report.skipped > 0 || report.chunk_point_errors > 0 || !report.skipped_data.empty());
}

}  // namespace

void register_render_command(CLI::App& app, std::function<int()>& run) {
    auto o = std::make_shared<RenderCliOptions>();
    auto* cmd = app.add_subcommand("render", "Render a dataset to a PNG without a window, as the viewer shows it once "
                                             "a stage (overview, heightmaps, full) is complete");
    add_inputs(*cmd, "paths", o->paths, kDatasetPathsHelp)->required();
    add_output(*cmd, "-o,--output", o->output, "The PNG to write", io::OutputKind::Png)->required();
    cmd->add_option("--camera", o->camera,
                    "X,Y,Z,YAW,PITCH (X,Y,Z in the CRS's units, as info prints them; degrees, yaw 0 = north, pitch "
                    "< 0 = down) or 'auto' (default: the whole dataset from the south, 60 degrees down)");
    cmd->add_option("--fov", o->fov, "Vertical field of view in degrees (default 60)");
    cmd->add_option("--size", o->size, "Image size WIDTHxHEIGHT (default 1280x720)");
    cmd->add_option("--until", o->until,
                    "Stage to complete: overview (chunk points), heightmaps, full (plus full-resolution points of "
                    "every tile in view that fits under --memory; default)");
    cmd->add_option("--colour,--color", o->colour, "rgb (default), elevation, intensity or classification");
    cmd->add_option("--heightmaps", o->heightmaps, "Heightmap method: linear (default) or cnn (the network)");
    cmd->add_option("--crs", o->crs,
                    "Reproject every tile to this CRS, e.g. EPSG:32632 (default: the CRS most tiles use)");
    cmd->add_option("--model", o->model, "TorchScript model for --heightmaps cnn (default: models/heightmap_cnn.pt)");
    cmd->add_option("--min-points", o->min_points,
                    "Chunk points a patch's 960 m window needs for a heightmap (default 6)")
        ->check(positive_number());
    cmd->add_option("--point-size", o->point_size,
                    "Full-resolution point size in pixels (default 1); near the camera points are drawn as wide as "
                    "their spacing on screen (up to 16 px) unless --fixed-point-size")
        ->check(CLI::Range(1, 64));
    cmd->add_flag("--fixed-point-size", o->fixed_point_size, "Every full-resolution point --point-size pixels wide");
    cmd->add_option("--chunk-point-size", o->chunk_point_size, "Chunk point size in pixels (default 2)")
        ->check(CLI::Range(1, 64));
    add_filter_options(*cmd, o->filter, "points read and drawn (chunk points: class and intensity only; a "
                                        "filter of classes 2 and/or 9 alone makes the heightmaps bare earth "
                                        "where full-resolution points were read, the rest tinted)");
    cmd->add_option("--edl", o->edl, "Eye-dome lighting strength (default 0 = off; try 1)")
        ->check(CLI::Range(0.0, 100.0));
    cmd->add_option("--memory", o->memory,
                    "Budget for full-resolution points, e.g. 2G (default: a quarter of the RAM)");
    add_thread_option(*cmd, "--threads", o->threads, "Worker threads (default: all cores)");
    cmd->add_option("--backend", o->backend,
                    "Rasterizer: cpu (default), cuda (the GPU plugin; an error when unavailable) or auto (cuda when "
                    "available, else cpu)");
    cmd->add_flag("--json", o->json, "Print the summary as JSON on stdout");
    cmd->callback([o, &run] { run = [o] { return run_render(*o); }; });
}

}  // namespace lidarscout::cli
