// make_dem: the grid, the rasters, the gridding (full, overview or products), the COGs, the hillshade
// and the contours, all under temporary names renamed together at the end (io::OutputGroup).
#include "raster/dem.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>

#include "core/error.hpp"
#include "core/process_memory.hpp"
#include "core/text.hpp"
#include "core/thread_pool.hpp"
#include "dataset/dataset.hpp"
#include "geo/geographic.hpp"
#include "io/output_group.hpp"
#include "raster/block_raster.hpp"
#include "raster/dem_grid.hpp"
#include "raster/contour_estimate.hpp"
#include "raster/contours.hpp"
#include "raster/dem_blocks.hpp"
#include "raster/hillshade.hpp"
#include "raster/overview_dem.hpp"

namespace lidarscout::raster {

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

constexpr std::pair<DemMethod, std::string_view> kMethodNames[] = {
    {DemMethod::Mean, "mean"}, {DemMethod::Min, "min"}, {DemMethod::Max, "max"}, {DemMethod::Idw, "idw"},
    {DemMethod::Tin, "tin"}, {DemMethod::Linear, "linear"}, {DemMethod::Cnn, "cnn"}};

bool fits(DemMethod m, DemSource s) {
    return (m == DemMethod::Linear || m == DemMethod::Cnn) == (s == DemSource::Overview);
}

GridderSpec gridder_of(const DemRequest& r) {
    GridderSpec g;
    g.method = r.method == DemMethod::Idw ? GridMethod::Idw : r.method == DemMethod::Tin ? GridMethod::Tin
                                                                                         : GridMethod::Statistic;
    g.statistic = r.method == DemMethod::Min ? recon::TexelStatistic::Min
                : r.method == DemMethod::Max ? recon::TexelStatistic::Max : recon::TexelStatistic::Mean;
    g.idw_radius_m = r.idw_radius_m;
    g.idw_power = r.idw_power;
    g.tin_max_edge_m = r.tin_max_edge_m;
    return g;
}

// A raster of over 2^30 texels of which the tiles cover under 5% is refused: tiles lying far
// apart (two surveys in one folder) would make a huge, nearly empty file for hours.
void check_mostly_empty(const dataset::Dataset& ds, const DemGrid& g) {
    const double texels = double(g.width) * g.height;
    if (texels <= double(1u << 30)) return;
    const double x1 = g.origin_x + g.width * g.texel_m, y1 = g.origin_y + g.height * g.texel_m;
    double covered = 0;
    for (const auto& t : ds.tiles) {
        const auto& b = t.bounds_m;
        covered += std::max(0.0, std::min(b.max_x, x1) - std::max(b.min_x, g.origin_x)) *
                   std::max(0.0, std::min(b.max_y, y1) - std::max(b.min_y, g.origin_y));
    }
    const double share = covered / (texels * g.texel_m * g.texel_m);
    if (share >= 0.05) return;
    char text[256];
    std::snprintf(text, sizeof text,
                  "the DEM would be %d x %d texels (%.0f GB as float32), but the tiles cover only %.2g%% of it "
                  "(they lie far apart): give --bounds, or a larger --texel", g.width, g.height, texels * 4 / 1e9,
                  100 * share);
    throw Error::in_stage("dem", text);
}

std::string gigabytes(double bytes) {
    char text[32];
    std::snprintf(text, sizeof text, "%.3g GB", bytes / 1e9);
    return text;
}

std::string number_text(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", v);
    return text;
}

// Refuses a DEM whose memory estimate exceeds the budget, suggesting a texel that fits (the
// estimate falls with the square of the texel).
void check_memory(const dataset::Dataset& ds, const DemGrid& g, const DemRequest& r, DemResult& result) {
    result.memory_estimate = dem_memory_bytes(ds, g, r);
    result.memory_budget = r.memory_budget ? r.memory_budget : usable_memory_bytes() / 2;
    const double need = static_cast<double>(result.memory_estimate);
    const double budget = static_cast<double>(result.memory_budget);
    if (need <= budget) return;
    const double texel = r.texel_m * std::sqrt(need / budget) * 1.1;
    const double step = std::pow(10.0, std::floor(std::log10(texel)) - 1);  // two significant digits
    char text[512];
    std::snprintf(text, sizeof text,
                  "the DEM would be %d x %d texels of %g m (%s as float32) and need about %s of memory at once, "
                  "over the budget of %s (%s): give a larger --texel (e.g. --texel %g), a smaller --bounds or "
                  "more --block pieces",
                  g.window().width, g.window().height, g.texel_m,
                  gigabytes(4.0 * g.window().width * g.window().height).c_str(), gigabytes(need).c_str(),
                  gigabytes(budget).c_str(), r.memory_budget ? "--memory" : "half of the memory this process may use",
                  std::ceil(texel / step) * step);
    throw Error::in_stage("dem", text);
}

// --bounds that miss every tile: refused with the data's bounds in the same units (the CRS's), and
// a hint when they look like degrees on a projected CRS.
void check_bounds_overlap(const dataset::Dataset& ds, const DemRequest& r, const Area& a) {
    const auto& b = ds.bounds_m;
    if (!r.area || (a.min_x < b.max_x && a.max_x > b.min_x && a.min_y < b.max_y && a.max_y > b.min_y)) return;
    const double f = ds.frame.xy_to_metres;
    const std::string unit = linear_unit_name(f);
    const bool degrees = geo::looks_like_degrees(r.area->min_x, r.area->min_y, r.area->max_x, r.area->max_y);
    char text[512];
    std::snprintf(text, sizeof text,
                  "--bounds %.10g,%.10g,%.10g,%.10g do not overlap the data, which lies in %.3f,%.3f,%.3f,%.3f "
                  "(xmin,ymin,xmax,ymax in the CRS's units%s%s)%s",
                  r.area->min_x, r.area->min_y, r.area->max_x, r.area->max_y,
                  b.min_x / f, b.min_y / f, b.max_x / f, b.max_y / f, unit.empty() ? "" : ": ", unit.c_str(),
                  degrees ? "; --bounds are not degrees" : "");
    throw Error::in_stage("dem", text);
}

// A DEM without a single point is an error, not an all-nodata file: nothing is written.
void check_points_used(const DemResult& result, const DemRequest& r) {
    if (result.points_used > 0 || r.block_count > 0) return;  // a piece of a DEM may be empty
    throw Error::in_stage("dem", r.filter.keeps_everything()
                                     ? "no point lies in the area; nothing written"
                                     : "no point of " + r.filter.describe() + " lies in the area (" +
                                           std::to_string(result.points_read) +
                                           " points read); nothing written: leave out --classes, --returns, "
                                           "--intensity or choose others");
}

int block_texels(const DemRequest& r) {
    if (r.source == DemSource::Overview) return kOverviewPatchTexels;
    if (!r.products.empty()) return ProductPass(r.products, r.product_options, r.texel_m).block_texels();
    return tin_block_texels(tin_margin_texels(gridder_of(r), r.texel_m));
}

// The request's area in metres, or the dataset's bounds.
Area area_in_metres(const dataset::Dataset& ds, const DemRequest& r) {
    if (!r.area) return dataset_area(ds);
    const double f = ds.frame.xy_to_metres;
    return {r.area->min_x * f, r.area->min_y * f, r.area->max_x * f, r.area->max_y * f};
}

void copy_stats(const FullDemStats& s, DemResult& result) {
    result.points_read = s.points_read;
    result.points_used = s.points_used;
    result.skipped = s.skipped;
    result.points_skipped = s.points_skipped;
    result.blocks_written = s.blocks_written;
    result.peak_blocks = s.peak_blocks;
    result.peak_held_points = s.peak_held_points;
}

RasterLayout height_layout(const dataset::Dataset& ds, float nodata) {
    RasterLayout l;
    l.nodata = nodata;
    l.unit = height_unit(ds.frame);
    l.description = "elevation";
    return l;
}

RasterLayout rgba_layout() {
    RasterLayout l;
    l.bands = 4;
    l.type = PixelType::Byte;
    l.alpha_last = true;
    return l;
}

void finish_raster(BlockRaster& raster, const DemRequest& r, io::OutputGroup& outputs) {
    raster.finish(r.threads, outputs, [&](double f) {
        if (r.progress) r.progress("cog", static_cast<std::uint64_t>(f * 1000), 1000);
    });
}

// The products of r.products in one pass: a raster each, made block by block from the shared layers.
void make_products(const dataset::Dataset& ds, const DemRequest& r, const RasterGeometry& geometry, float nodata,
                   DemResult& result, io::OutputGroup& outputs) {
    if (r.source != DemSource::Full) throw Error::in_stage("dem", "--product applies to --from full only");
    if (!r.rgb.empty()) throw Error::in_stage("dem", "--rgb does not apply to --product");
    const ProductPass pass(r.products, r.product_options, r.texel_m);
    result.outputs = product_paths(r.output, r.products);
    std::vector<std::unique_ptr<BlockRaster>> rasters;
    for (std::size_t i = 0; i < r.products.size(); ++i) {
        rasters.push_back(std::make_unique<BlockRaster>(result.outputs[i], geometry,
                                                        pass.layout(r.products[i], height_unit(ds.frame), nodata)));
    }
    const DemGrid& grid = result.grid;
    const BlockWriteFn write = [&](lidarscout::CellKey c, std::vector<BlockImages>& layers) {
        for (std::size_t i = 0; i < r.products.size(); ++i) {
            const std::vector<float> values = pass.values(r.products[i], layers, ds.frame.z_to_metres, nodata);
            write_block(*rasters[i], grid, 1, c.ix, c.iy, std::span<const float>(values));
        }
    };
    ThreadPool pool(std::max(1u, r.threads));
    auto t0 = Clock::now();
    const FullDemStats stats = grid_full_layers(ds, grid, pass.layers(), write, pool,
                                                [&](std::uint64_t done, std::uint64_t total) {
                                                    if (r.progress) r.progress("points", done, total);
                                                });
    copy_stats(stats, result);
    result.seconds_grid = seconds_since(t0);
    if (r.block_count == 0) {  // a piece of a DEM may be empty
        pass.check_points(r.products, stats.layer_points, result.points_read);  // names the empty product
        if (result.points_used == 0) {
            throw Error::in_stage("dem", "no point of the products lies in the area; nothing written");
        }
    }
    t0 = Clock::now();
    for (auto& raster : rasters) finish_raster(*raster, r, outputs);
    result.seconds_cog = seconds_since(t0);
}

// --block I/N: the grid's piece I of N, for what a piece can make.
void select_piece(const dataset::Dataset& ds, const DemRequest& r, DemGrid& grid) {
    if (r.source != DemSource::Full) throw Error::in_stage("dem", "--block applies to --from full only");
    if (!r.hillshade.empty() || r.contours_interval > 0) {
        throw Error::in_stage("dem", std::string(r.hillshade.empty() ? "--contours" : "--hillshade") +
                                         " does not apply to --block (make it from the mosaic of the pieces)");
    }
    if (r.block_index < 1 || r.block_index > r.block_count) {
        throw Error::in_stage("dem", "--block I/N needs 1 <= I <= N (internal error)");
    }
    grid.selection = dem_block_pieces(ds, grid, r.block_count)[static_cast<std::size_t>(r.block_index - 1)];
}

// The contours of `heights` counted before GDAL draws them (contour_estimate.hpp): refused past the
// line limit or the memory budget, with the finest interval of 1, 2 or 5 times a power of ten that
// stays under both; the memory estimate then covers them.
void check_contours(const std::string& heights, const DemRequest& r, float nodata, DemResult& result) {
    const std::vector<ContourCount> counts = count_contours(heights, nodata, contour_intervals(r.contours_interval));
    const double texels = double(result.grid.window().width) * result.grid.window().height;
    const auto lines_fit = [&](const ContourCount& c) {
        return r.contour_line_limit == 0 || c.lines <= static_cast<double>(r.contour_line_limit);
    };
    const auto fits = [&](const ContourCount& c) {
        return lines_fit(c) && contour_memory_bytes(c, texels) <= result.memory_budget;
    };
    const ContourCount& asked = counts.front();
    result.contour_lines_estimate = asked.lines, result.contour_points_estimate = asked.vertices;
    result.memory_estimate = std::max(result.memory_estimate, contour_memory_bytes(asked, texels));
    if (fits(asked)) return;
    std::string text = "--contours " + number_text(asked.interval) + " would draw about " + count_text(asked.lines) +
                       " lines of " + count_text(asked.vertices) + " points";
    if (!lines_fit(asked)) {
        text += " (limit " + count_text(static_cast<double>(r.contour_line_limit)) + " lines)";
    } else {
        text += " and need about " + gigabytes(double(contour_memory_bytes(asked, texels))) +
                " of memory, over the budget of " + gigabytes(double(result.memory_budget));
    }
    const auto coarser = std::find_if(counts.begin() + 1, counts.end(), fits);
    if (coarser != counts.end()) {
        text += ": try --contours " + number_text(coarser->interval) + " (about " + count_text(coarser->lines) +
                " lines)";
    }
    if (!lines_fit(asked)) text += coarser != counts.end() ? ", or --force to draw them all" : ": give --force";
    throw Error::in_stage("dem", text);
}

// The hillshade and the contours of the height raster, once it is written (under its temporary name).
void write_from_heights(const DemRequest& r, float nodata, DemResult& result, io::OutputGroup& outputs) {
    const std::string heights = contour_source(r);
    if (r.contours_interval > 0) {  // before any of the two is made
        check_contours(outputs.path_of(heights), r, nodata, result);
    }
    if (!r.hillshade.empty()) {
        const auto t0 = Clock::now();
        write_hillshade(heights, r.hillshade, outputs);
        result.seconds_hillshade = seconds_since(t0);
    }
    if (r.contours_interval > 0) {
        const auto t0 = Clock::now();
        result.contours = contours_path(heights);
        const auto progress = [&](double f) {
            if (r.progress) r.progress("contours", static_cast<std::uint64_t>(f * 1000), 1000);
        };
        result.contour_lines = write_contours(heights, result.contours, r.contours_interval, nodata, outputs, progress);
        result.seconds_contours = seconds_since(t0);
    }
}

}  // namespace

DemSource dem_source_from_name(std::string_view name) {
    if (name == "full") return DemSource::Full;
    if (name == "overview") return DemSource::Overview;
    throw Error("--from must be overview or full (not '" + std::string(name) + "')");
}

DemMethod dem_method_from_name(std::string_view name, DemSource source) {
    for (const auto& [m, n] : kMethodNames) {
        if (n != name) continue;
        if (!fits(m, source)) {
            throw Error("--method " + std::string(name) + " does not fit --from " +
                        (source == DemSource::Full ? "full (mean, min, max, idw or tin)" : "overview (linear or cnn)"));
        }
        return m;
    }
    throw Error("unknown --method '" + std::string(name) +
                "' (mean, min, max, idw, tin for full; linear, cnn for overview)");
}

std::string_view dem_method_name(DemMethod method) {
    for (const auto& [m, n] : kMethodNames) {
        if (m == method) return n;
    }
    return "?";
}

std::uint64_t dem_memory_bytes(const dataset::Dataset& ds, const DemGrid& g, const DemRequest& r) {
    const double tiff_tiles = std::ceil(g.window().width / 512.0) * std::ceil(g.window().height / 512.0);
    const double rasters = r.rgb.empty() ? 1 : 2;
    double bytes = tiff_tiles * rasters * 2 * 16;  // scratch and COG: an offset and a size per tile
    if (!r.products.empty()) {
        bytes = tiff_tiles * static_cast<double>(r.products.size()) * 2 * 16;
        const ProductPass pass(r.products, r.product_options, r.texel_m);
        bytes += static_cast<double>(full_layers_peak_bytes(ds, g, pass.layers()));
    } else if (r.source == DemSource::Full) {
        bytes += static_cast<double>(full_dem_peak_bytes(ds, g, gridder_of(r), !r.rgb.empty()));
    }
    return bytes >= 1.8e19 ? ~0ull : static_cast<std::uint64_t>(bytes);
}

std::string contour_source(const DemRequest& r) {
    if (r.products.empty()) return r.output;
    const auto height = std::find_if(r.products.begin(), r.products.end(), is_height_product);
    if (height == r.products.end()) return {};
    return product_paths(r.output, r.products)[static_cast<std::size_t>(height - r.products.begin())];
}

double dem_reach_m(const DemRequest& r) {
    const double block_m = block_texels(r) * r.texel_m;
    return 2 * block_m + std::max(gridder_reach_m(gridder_of(r), r.texel_m), 0.0);
}

DemGrid dem_grid(const dataset::Dataset& ds, const DemRequest& r) {
    const Area area = area_in_metres(ds, r);
    check_bounds_overlap(ds, r, area);
    return make_dem_grid(area, r.texel_m, block_texels(r));
}

DemResult make_dem(const dataset::Dataset& ds, const DemRequest& r) {
    if (!fits(r.method, r.source)) throw Error::in_stage("dem", "the method does not fit the source");
    if (!r.hillshade.empty()) hillshade_is_png(r.hillshade);  // an unknown extension refused before any work
    if ((!r.hillshade.empty() || r.contours_interval > 0) && contour_source(r).empty()) {
        throw Error::in_stage("dem", std::string(r.hillshade.empty() ? "--contours" : "--hillshade") +
                                         " needs a dtm, dsm or chm product");
    }
    if (r.contours_interval < 0 || !std::isfinite(r.contours_interval)) {
        throw Error::in_stage("dem", "--contours must be a positive interval");
    }
    DemResult result;
    result.grid = dem_grid(ds, r);
    check_mostly_empty(ds, result.grid);
    if (r.block_count > 0) select_piece(ds, r, result.grid);
    check_memory(ds, result.grid, r, result);
    const RasterGeometry geometry = raster_geometry(result.grid, ds.frame);
    const float nodata = -9999.0f;
    io::OutputGroup files;  // every file of the run appears at the end, or none does
    if (!r.products.empty()) {
        make_products(ds, r, geometry, nodata, result, files);
        write_from_heights(r, nodata, result, files);
        files.commit();
        return result;
    }
    result.outputs = {r.output};
    if (!r.rgb.empty()) result.outputs.push_back(r.rgb);
    BlockRaster heights(r.output, geometry, height_layout(ds, nodata));
    std::unique_ptr<BlockRaster> rgb;
    if (!r.rgb.empty()) rgb = std::make_unique<BlockRaster>(r.rgb, geometry, rgba_layout());
    const DemOutputs outputs{&heights, rgb.get(), ds.frame.z_to_metres};
    ThreadPool pool(std::max(1u, r.threads));
    auto t0 = Clock::now();
    if (r.source == DemSource::Full) {
        FullDemOptions opt;
        opt.gridder = gridder_of(r);
        opt.filter = r.filter;
        opt.nodata = nodata;
        opt.progress = [&](std::uint64_t done, std::uint64_t total) {
            if (r.progress) r.progress("points", done, total);
        };
        copy_stats(grid_full_dem(ds, result.grid, opt, outputs, pool), result);
    } else {
        OverviewDemOptions opt;
        opt.network = r.method == DemMethod::Cnn;
        opt.model = r.model;
        opt.filter = r.filter;
        opt.nodata = nodata;
        opt.progress = [&](std::uint64_t done, std::uint64_t total) {
            if (r.progress) r.progress("patches", done, total);
        };
        const OverviewDemStats s = grid_overview_dem(ds, result.grid, opt, outputs, pool);
        result.points_read = result.points_used = s.chunk_points;
        result.skipped = s.skipped;
        result.points_skipped = s.chunk_points_skipped;
        result.blocks_written = s.patches_written;
    }
    result.seconds_grid = seconds_since(t0);
    check_points_used(result, r);
    t0 = Clock::now();
    finish_raster(heights, r, files);
    if (rgb) finish_raster(*rgb, r, files);
    result.seconds_cog = seconds_since(t0);
    write_from_heights(r, nodata, result, files);
    files.commit();
    return result;
}

}  // namespace lidarscout::raster
