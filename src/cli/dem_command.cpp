// `lidarscout dem PATH... -o out.tif [--texel 1] [--bounds xmin,ymin,xmax,ymax] [--from full|overview]
// [--method mean|min|max|idw|tin|linear|cnn] [--radius M] [--power P] [--max-edge M] [--classes 2,9]
// [--returns first,last,single,intermediate] [--intensity MIN-MAX] [--ground classes|smrf] [--ground-cell M]
// [--ground-slope S] [--ground-window M] [--ground-threshold M]
// [--crs EPSG:n] [--rgb out_rgb.tif] [--hillshade out.png] [--contours INTERVAL [--force]] [--block I/N]
// [--memory SIZE] [--threads N] [--json]`:
// a terrain or surface model of a dataset as a float32 Cloud-Optimized
// GeoTIFF in the tiles' CRS, from every point or from the overview (raster/dem.hpp); with
// `--product dtm,dsm,chm,density,pulse-density,intensity,count` those rasters instead, in one read of
// the points (raster/products.hpp), each to OUT_NAME.tif (to OUT.tif when there is one); contour
// lines of the height raster to RASTER_contours.gpkg (raster/contours.hpp). `--block I/N` makes piece I
// of N of the grid only (raster/dem_blocks.hpp: the pieces mosaic into the whole run exactly; the Dask
// driver python/lidarscout_dask runs them on a cluster); `--memory` bounds what the DEM may hold.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <optional>
#include <thread>
#include <tuple>

#include "cli/commands.hpp"
#include "cli/json_output.hpp"
#include "cli/filter_options.hpp"
#include "cli/number_options.hpp"
#include "cli/io_options.hpp"
#include "cli/diagnostic_output.hpp"
#include "cli/progress.hpp"
#include "cli/recon_options.hpp"
#include "cli/size_options.hpp"
#include "cli/region_options.hpp"
#include "cli/stage_progress.hpp"
#include "cli/thread_options.hpp"
#include "core/error.hpp"
#include "core/process_memory.hpp"
#include "core/text.hpp"
#include "dataset/dataset.hpp"
#include "raster/contours.hpp"
#include "raster/dem.hpp"
#include "raster/dem_options.hpp"

namespace lidarscout::cli {
namespace {

// dem's own options (raster/dem_options.hpp) and the command line's: the inputs, the plan, the printing.
struct DemCliOptions {
    std::vector<std::string> paths;
    raster::DemOptions dem;
    FilterTexts filter;  // into dem's classes, returns, intensity
    std::string crs;
    int plan = 0;        // --plan N: print the N pieces, make nothing
    std::string memory;  // the budget ("4G"), empty: half of what the process may use
    bool json = false;
};

// One progress bar per stage, made when the stage first reports.
class StageBars {
public:
    void update(std::string_view stage, std::uint64_t done, std::uint64_t total) {
        auto& bar = bars_[std::string(stage)];
        if (!bar) bar = std::make_unique<Progress>(label(stage), total);
        bar->set_total(total);
        bar->add(done - shown_[std::string(stage)]);
        shown_[std::string(stage)] = done;
    }

private:
    static std::string label(std::string_view stage) {
        if (stage == "points") return "dem: points";
        if (stage == "patches") return "dem: patches";
        if (stage == "contours") return "dem: contours";
        return "dem: writing COG";
    }
    std::map<std::string, std::unique_ptr<Progress>> bars_;
    std::map<std::string, std::uint64_t> shown_;
};

raster::DemRequest make_request(const DemCliOptions& o) {
    raster::DemOptions d = o.dem;
    d.classes = o.filter.classes, d.returns = o.filter.returns, d.intensity = o.filter.intensity;
    if (!o.memory.empty()) d.memory = parse_bytes(o.memory, "--memory");
    return raster::dem_request(d);
}

// --block: which piece, its blocks of the grid and its texels in the whole raster (column, row from the north).
nlohmann::json block_json(const raster::DemRequest& r, const raster::DemGrid& g) {
    const raster::BlockRange b = g.selected_blocks();
    const raster::DemGrid::Window w = g.window();
    return {{"index", r.block_index},
            {"count", r.block_count},
            {"blocks", {b.x0, b.y0, b.x1, b.y1}},
            {"grid_width", g.width},
            {"grid_height", g.height},
            {"window", {w.col, w.row, w.width, w.height}}};
}

void print_result(const DemCliOptions& o, const raster::DemRequest& r, const raster::DemResult& d, double seconds) {
    if (o.json) {
        nlohmann::json j = {{"output", r.output},
                            {"rgb", r.rgb.empty() ? nlohmann::json(nullptr) : nlohmann::json(r.rgb)},
                            {"hillshade", r.hillshade.empty() ? nlohmann::json(nullptr) : nlohmann::json(r.hillshade)},
                            {"from", o.dem.from},
                            {"method", std::string(raster::dem_method_name(r.method))},
                            {"texel_m", r.texel_m},
                            {"width", d.grid.width},
                            {"height", d.grid.height},
                            {"origin_m", {d.grid.origin_x, d.grid.origin_y}},
                            {"points_read", d.points_read},
                            {"points_used", d.points_used},
                            {"points_skipped", d.points_skipped},
                            {"skipped_chunks", skipped_json(d.skipped)},
                            {"blocks_written", d.blocks_written},
                            {"peak_blocks", d.peak_blocks},
                            {"peak_held_points", d.peak_held_points},
                            {"seconds_grid", d.seconds_grid},
                            {"seconds_cog", d.seconds_cog},
                            {"memory_estimate_bytes", d.memory_estimate},
                            {"memory_budget_bytes", d.memory_budget},
                            {"peak_resident_bytes", peak_resident_bytes()},
                            {"seconds_hillshade", d.seconds_hillshade},
                            {"seconds", seconds}};
        if (!r.products.empty()) {
            j.erase("method");
            j["products"] = nlohmann::json::object();
            for (std::size_t i = 0; i < r.products.size(); ++i) {
                j["products"][std::string(raster::product_name(r.products[i]))] = d.outputs[i];
            }
            j["max_edge_m"] = raster::ProductPass(r.products, r.product_options, r.texel_m).max_edge_m();
            if (const auto& g = r.product_options.ground) {
                j["ground"] = {{"filter", "smrf"}, {"cell_m", g->cell_m},
                               {"slope", g->slope > 0 ? nlohmann::json(g->slope) : nlohmann::json("terrain")},
                               {"window_m", g->window_m}, {"threshold_m", g->threshold_m}, {"scalar", g->scalar}};
            }
        }
        if (r.block_count > 0) j["block"] = block_json(r, d.grid);
        if (!d.contours.empty()) {
            j["contours"] = d.contours;
            j["contour_lines"] = d.contour_lines;
            j["contour_lines_estimate"] = std::llround(d.contour_lines_estimate);
            j["contour_points_estimate"] = std::llround(d.contour_points_estimate);
            j["seconds_contours"] = d.seconds_contours;
        }
        print_json_answer(j);
        return;
    }
    std::string what = std::string(raster::dem_method_name(r.method));
    if (!r.products.empty()) what = "products: " + o.dem.product;
    std::printf("%s: %d x %d texels of %g m (%s, %s), %llu of %llu points used, %.2f s (gridding %.2f s, COG %.2f s)\n",
                r.output.c_str(), d.grid.window().width, d.grid.window().height, r.texel_m, o.dem.from.c_str(),
                what.c_str(),
                (unsigned long long)d.points_used, (unsigned long long)d.points_read, seconds, d.seconds_grid,
                d.seconds_cog);
    if (!r.products.empty()) {
        for (std::size_t i = 0; i < r.products.size(); ++i) {
            std::printf("%s: %s\n", d.outputs[i].c_str(), std::string(raster::product_name(r.products[i])).c_str());
        }
    }
    if (r.block_count > 0) {
        const raster::DemGrid::Window w = d.grid.window();
        std::printf("piece %d of %d: texels %d..%d x %d..%d (rows from the north) of the %d x %d grid\n",
                    r.block_index, r.block_count, w.col, w.col + w.width - 1, w.row, w.row + w.height - 1,
                    d.grid.width, d.grid.height);
    }
    std::printf("memory: estimated %.3g GB (budget %.3g GB), peak resident %.3g GB\n", d.memory_estimate / 1e9,
                d.memory_budget / 1e9, peak_resident_bytes() / 1e9);
    if (!r.rgb.empty()) std::printf("%s: orthophoto (RGBA)\n", r.rgb.c_str());
    if (!r.hillshade.empty()) std::printf("%s: hillshade\n", r.hillshade.c_str());
    if (!d.contours.empty()) {
        std::printf("%s: %llu contour lines every %g\n", d.contours.c_str(), (unsigned long long)d.contour_lines,
                    r.contours_interval);
    }
}

// --plan N: the grid and its N pieces (for --block I/N) with the points the tile headers put in
// each and the memory each is estimated to need, as the Dask driver reads them; nothing is made.
int print_plan(const DemCliOptions& o, const dataset::Dataset& ds, const raster::DemRequest& r) {
    const raster::DemPlan plan = raster::dem_plan(ds, r, o.plan);
    const raster::DemGrid& grid = plan.grid;
    nlohmann::json pieces = nlohmann::json::array();
    for (const raster::DemPiece& p : plan.pieces) {
        const raster::BlockRange& b = p.blocks;
        const raster::DemGrid::Window& w = p.window;
        pieces.push_back({{"index", p.index}, {"blocks", {b.x0, b.y0, b.x1, b.y1}},
                          {"window", {w.col, w.row, w.width, w.height}}, {"points", std::llround(p.points)},
                          {"memory_estimate_bytes", p.memory_estimate}});
    }
    const std::uint64_t total = plan.points;
    const nlohmann::json j = {{"width", grid.width},         {"height", grid.height},
                              {"texel_m", grid.texel_m},     {"block_texels", grid.block},
                              {"blocks", plan.blocks},       {"tiles", ds.tiles.size()},
                              {"points", total},             {"pieces", pieces}};
    if (o.json) {
        print_json_answer(j);
        return 0;
    }
    std::printf("%d x %d texels of %g m in %lld blocks of %d texels, %zu tiles, %llu points; %d pieces:\n", grid.width,
                grid.height, grid.texel_m, (long long)plan.blocks, grid.block, ds.tiles.size(),
                (unsigned long long)total, o.plan);
    for (const auto& p : pieces) {
        std::printf("  --block %d/%d: texels %d x %d at column %d, row %d; about %lld points, %.3g GB\n",
                    p["index"].get<int>(), o.plan, p["window"][2].get<int>(), p["window"][3].get<int>(),
                    p["window"][0].get<int>(), p["window"][1].get<int>(), p["points"].get<long long>(),
                    p["memory_estimate_bytes"].get<double>() / 1e9);
    }
    return 0;
}

int run_dem(const DemCliOptions& o) {
    const auto t0 = std::chrono::steady_clock::now();
    raster::DemRequest r = make_request(o);
    dataset::DatasetOptions dataset_options;
    dataset_options.crs = o.crs;
    // A DEM of an area from every point reads only the headers of the tiles near it (a placed catalog's).
    dataset_options.placed = r.area && r.source == raster::DemSource::Full;
    dataset::Dataset ds = open_with_progress(o.paths, dataset_options);
    if (ds.placed) {
        const double m = raster::dem_reach_m(r) / ds.frame.xy_to_metres;  // (the area is in the CRS's units)
        const raster::Area a = *r.area;
        dataset::keep_tiles_touching(ds, [&](const dataset::Bounds& b) {
            return b.max_x >= a.min_x - m && b.min_x <= a.max_x + m && b.max_y >= a.min_y - m && b.min_y <= a.max_y + m;
        });
    }
    for (const auto& s : ds.skipped) std::fprintf(stderr, "lidarscout: skipped %s\n", s.error.c_str());
    print_diagnostics(ds.warnings);
    dataset::require_tiles(ds, "dem");
    if (o.plan > 0) return print_plan(o, ds, r);
    StageBars bars;
    r.progress = [&](std::string_view stage, std::uint64_t done, std::uint64_t total) {
        bars.update(stage, done, total);
    };
    const raster::DemResult d = raster::make_dem(ds, r);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    print_skipped(d.skipped);
    print_result(o, r, d, seconds);
    return written_exit_status(!d.skipped.empty() || !ds.skipped.empty());
}

}  // namespace

void register_dem_command(CLI::App& app, std::function<int()>& run) {
    auto o = std::make_shared<DemCliOptions>();
    auto* cmd = app.add_subcommand(
        "dem", "Write a DEM (float32 Cloud-Optimized GeoTIFF) from every point or from the overview");
    add_inputs(*cmd, "paths", o->paths, "LAS/LAZ files, folders (searched recursively) or text files listing tiles")
        ->required();
    add_output(*cmd, "-o,--output", o->dem.output, "The DEM to write (.tif)", io::OutputKind::GeoTiff)->required();
    cmd->add_option("--texel", o->dem.texel, "Texel size in metres (default 1)")->check(positive_number());
    cmd->add_option("--bounds", o->dem.bounds, "xmin,ymin,xmax,ymax in the CRS's units (default: the whole dataset)")
        ->delimiter(',')->expected(4);
    cmd->add_option("--from", o->dem.from, "full (every point) or overview (chunk points only; default full)");
    cmd->add_option("--method", o->dem.method,
                    "full: mean (default), min, max, idw, tin; overview: linear (default), cnn");
    cmd->add_option("--radius", o->dem.radius,
                    "idw: search radius around each texel centre, metres (default: texel x 1.414)")
        ->check(positive_number());
    cmd->add_option("--power", o->dem.power, "idw: weights 1 / distance^power (default 2)")->check(positive_number());
    cmd->add_option("--max-edge", o->dem.max_edge,
                    "tin: no height in triangles with a longer edge, metres (default 0: no limit); --product "
                    "dtm, dsm, chm: the same (default 20 texels)")
        ->check(non_negative_number());
    cmd->add_option("--product", o->dem.product,
                    "Instead of one DEM, these rasters in one read of the points, separated by commas: dtm "
                    "(TIN of the --classes, default 2,9), dsm (highest first return, holes by TIN), chm (dsm - dtm), "
                    "density, pulse-density (per m2), intensity (mean), count; several go to OUT_NAME.tif");
    cmd->add_option("--ground", o->dem.ground,
                    "The dtm's ground: classes (the --classes, default 2,9) or smrf (found among every point but "
                    "noise, or among the --classes, by the simple morphological filter: for unclassified surveys)");
    const auto ground_option = [&](const char* name, double& value, const char* help) {
        cmd->add_option(name, value, help)->each([o, name](const std::string&) {
            o->dem.ground_options.push_back(name);
        });
    };
    ground_option("--ground-cell", o->dem.ground_params.cell_m,
                  "smrf: cell of its minimum surface, metres (default 1; larger where the points are sparser)");
    ground_option("--ground-slope", o->dem.ground_params.slope,
                  "smrf: the steepest ground, rise over run (default: the terrain's, from the lowest points "
                  "of window-sized cells, at least 0.15)");
    ground_option("--ground-window", o->dem.ground_params.window_m,
                  "smrf: the largest object's half-width, metres (default 18)");
    ground_option("--ground-threshold", o->dem.ground_params.threshold_m,
                  "smrf: the height above or below the ground surface still ground, metres (default 0.5)");
    cmd->add_option("--contours", o->dem.contours,
                    "Also write contour lines every INTERVAL (the raster's height unit) of the DEM, or of the first "
                    "dtm, dsm or chm product, to RASTER_contours.gpkg (GeoPackage, attribute elevation)")
        ->check(positive_number());
    cmd->add_flag("--force", o->dem.force,
                  "Draw the --contours even when they are counted at more than " +
                      count_text(double(raster::kContourLineLimit)) +
                      " lines (refused otherwise, before they are drawn)");
    add_derived_outputs(*cmd, [o] {
        std::vector<io::OutputTarget> out;
        if (o->dem.output.empty()) return out;
        raster::DemRequest r;
        r.output = o->dem.output;
        if (!o->dem.product.empty()) r.products = raster::products_from_names(o->dem.product);
        const auto paths = raster::product_paths(o->dem.output, r.products);
        for (std::size_t i = 0; r.products.size() > 1 && i < paths.size(); ++i) {  // one product is -o itself
            out.push_back({paths[i], "-o/--output (--product " + std::string(raster::product_name(r.products[i])) + ")",
                           io::OutputKind::GeoTiff});
        }
        const std::string heights = raster::contour_source(r);
        if (o->dem.contours && !heights.empty()) {
            out.push_back({raster::contours_path(heights), "--contours", io::OutputKind::GeoPackage});
        }
        return out;
    });
    add_filter_options(*cmd, o->filter,
                       "points gridded (--returns with --from full only: the overview's chunk points have no "
                       "reliable returns)");
    cmd->add_option("--crs", o->crs, "Write the DEM in this CRS, e.g. EPSG:32616 (default: the CRS most tiles use)");
    add_output(*cmd, "--rgb", o->dem.rgb,
               "Also write the orthophoto (RGBA Cloud-Optimized GeoTIFF of the point colours)",
               io::OutputKind::GeoTiff);
    add_output(*cmd, "--hillshade", o->dem.hillshade,
               "Also write a hillshade of the DEM: .tif (GeoTIFF) or .png (with its world file .pgw, .aux.xml)",
               io::OutputKind::Hillshade);
    cmd->add_option("--model", o->dem.model, "The heightmap network for --method cnn (default: the shipped model)");
    cmd->add_option("--block", o->dem.block,
                    "Make only piece I of N (e.g. 3/16) of the DEM's grid (of the whole dataset or --bounds), cut "
                    "by point count: the N pieces mosaic into one whole run texel for texel (--from full; the Dask "
                    "driver python3 -m lidarscout_dask runs them on a cluster)");
    cmd->add_option("--plan", o->plan,
                    "Print the N pieces of --block I/N (their texels and the points the tile headers put in them) "
                    "and make nothing")
        ->check(CLI::PositiveNumber);
    cmd->add_option("--memory", o->memory,
                    "Memory the DEM may hold at once, e.g. 4G (default: half of what this process may use); a DEM "
                    "estimated to need more is refused before any work");
    add_thread_option(*cmd, "--threads", o->dem.threads, "Threads (default: all cores)");
    cmd->add_flag("--json", o->json, "Print the result as JSON");
    cmd->callback([o, &run] { run = [o] { return run_dem(*o); }; });
}

}  // namespace lidarscout::cli
