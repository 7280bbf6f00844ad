// make_dem: the grid, the rasters, the gridding (full or overview), the COGs, the hillshade.
#include "raster/dem.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>

#include "core/error.hpp"
#include "core/thread_pool.hpp"
#include "dataset/dataset.hpp"
#include "raster/block_raster.hpp"
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

int block_texels(const DemRequest& r) {
    if (r.source == DemSource::Overview) return kOverviewPatchTexels;
    return r.method == DemMethod::Tin ? kTinBlockTexels : 512;
}

// The request's area in metres, or the dataset's bounds.
Area area_in_metres(const dataset::Dataset& ds, const DemRequest& r) {
    if (!r.area) return dataset_area(ds);
    const double f = ds.frame.xy_to_metres;
    return {r.area->min_x * f, r.area->min_y * f, r.area->max_x * f, r.area->max_y * f};
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

void finish_raster(BlockRaster& raster, const DemRequest& r) {
    raster.finish(r.threads, [&](double f) {
        if (r.progress) r.progress("cog", static_cast<std::uint64_t>(f * 1000), 1000);
    });
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

DemResult make_dem(const dataset::Dataset& ds, const DemRequest& r) {
    if (!fits(r.method, r.source)) throw Error::in_stage("dem", "the method does not fit the source");
    if (!r.hillshade.empty()) hillshade_is_png(r.hillshade);  // an unknown extension refused before any work
    DemResult result;
    result.grid = make_dem_grid(area_in_metres(ds, r), r.texel_m, block_texels(r));
    check_mostly_empty(ds, result.grid);
    const RasterGeometry geometry = raster_geometry(result.grid, ds.frame);
    const float nodata = -9999.0f;
    BlockRaster heights(r.output, geometry, height_layout(ds, nodata));
    std::unique_ptr<BlockRaster> rgb;
    if (!r.rgb.empty()) rgb = std::make_unique<BlockRaster>(r.rgb, geometry, rgba_layout());
    const DemOutputs outputs{&heights, rgb.get(), ds.frame.z_to_metres};
    ThreadPool pool(std::max(1u, r.threads));
    auto t0 = Clock::now();
    if (r.source == DemSource::Full) {
        FullDemOptions opt;
        opt.gridder = gridder_of(r);
        opt.classes = ClassFilter::only(r.classes);
        opt.nodata = nodata;
        opt.progress = [&](std::uint64_t done, std::uint64_t total) {
            if (r.progress) r.progress("points", done, total);
        };
        const FullDemStats s = grid_full_dem(ds, result.grid, opt, outputs, pool);
        result.points_read = s.points_read;
        result.points_used = s.points_used;
        result.blocks_written = s.blocks_written;
        result.peak_blocks = s.peak_blocks;
    } else {
        OverviewDemOptions opt;
        opt.network = r.method == DemMethod::Cnn;
        opt.model = r.model;
        opt.classes = ClassFilter::only(r.classes);
        opt.nodata = nodata;
        opt.progress = [&](std::uint64_t done, std::uint64_t total) {
            if (r.progress) r.progress("patches", done, total);
        };
        const OverviewDemStats s = grid_overview_dem(ds, result.grid, opt, outputs, pool);
        result.points_read = result.points_used = s.chunk_points;
        result.blocks_written = s.patches_written;
    }
    result.seconds_grid = seconds_since(t0);
    t0 = Clock::now();
    finish_raster(heights, r);
    if (rgb) finish_raster(*rgb, r);
    result.seconds_cog = seconds_since(t0);
    if (!r.hillshade.empty()) {
        t0 = Clock::now();
        write_hillshade(r.output, r.hillshade);
        result.seconds_hillshade = seconds_since(t0);
    }
    return result;
}

}  // namespace lidarscout::raster
