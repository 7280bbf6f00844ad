// dem_request and dem_plan (see dem_options.hpp): moved from the CLI's `dem` so that the Python module
// makes the same requests.
#include "raster/dem_options.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <thread>
#include <tuple>

#include "core/error.hpp"
#include "dataset/dataset.hpp"
#include "raster/dem_blocks.hpp"

namespace lidarscout::raster {
namespace {

// The numbers a command line checks as it reads them, checked again for callers that are not one.
void check_numbers(const DemOptions& o) {
    const auto check = [](const std::optional<double>& v, const char* option, bool zero_allowed) {
        if (v && !(std::isfinite(*v) && (*v > 0 || (zero_allowed && *v == 0)))) {
            char text[32];
            std::snprintf(text, sizeof text, "%g", *v);
            throw Error(std::string("dem: ") + option + ": must be " + (zero_allowed ? "0 or more" : "more than 0") +
                        ", not '" + text + "'");  // (as the CLI's number checks say it)
        }
    };
    check(o.texel, "--texel", false);
    check(o.radius, "--radius", false);
    check(o.power, "--power", false);
    check(o.max_edge, "--max-edge", true);
    check(o.contours, "--contours", false);
    if (!o.bounds.empty() && o.bounds.size() != 4) {
        throw Error("dem: --bounds expects four numbers: xmin,ymin,xmax,ymax");
    }
}

// --radius and --power (idw) and --max-edge (tin), refused with another method.
void apply_method_parameters(const DemOptions& o, DemRequest& r) {
    const auto only_for = [&](const std::optional<double>& v, const char* option, DemMethod method) {
        if (v && r.method != method) {
            throw Error(std::string("dem: ") + option + " applies to --method " + std::string(dem_method_name(method)) +
                        " only");
        }
        return v.has_value();
    };
    if (only_for(o.radius, "--radius", DemMethod::Idw)) r.idw_radius_m = *o.radius;
    if (only_for(o.power, "--power", DemMethod::Idw)) r.idw_power = *o.power;
    if (only_for(o.max_edge, "--max-edge", DemMethod::Tin)) r.tin_max_edge_m = *o.max_edge;
}

// --ground smrf and its parameters (--ground-*), for a dtm or chm only.
void apply_ground(const DemOptions& o, DemRequest& r) {
    if (o.ground != "smrf") {
        if (o.ground != "classes") throw Error("dem: --ground must be classes or smrf (it is '" + o.ground + "')");
        if (!o.ground_options.empty()) throw Error("dem: " + o.ground_options.front() + " applies to --ground smrf");
        return;
    }
    const bool terrain = std::any_of(r.products.begin(), r.products.end(), [](Product p) {
        return p == Product::Dtm || p == Product::Chm;
    });
    if (!terrain) throw Error("dem: --ground applies to the dtm and chm products");
    const auto given = [&](const char* name) {
        return std::find(o.ground_options.begin(), o.ground_options.end(), std::string(name)) != o.ground_options.end();
    };
    if (given("--ground-slope") && !(o.ground_params.slope > 0)) {  // 0 stands for the terrain's: not to be typed
        throw Error("dem: --ground-slope must be a positive rise over run (leave it out for the terrain's)");
    }
    recon::check_ground_params(o.ground_params);
    r.product_options.ground = o.ground_params;
}

// --product: the products, the dtm's classes (--classes) and the maximum edge (--max-edge); the
// options that choose points or a method another way are refused.
void apply_products(const DemOptions& o, DemRequest& r) {
    r.products = products_from_names(o.product);
    const auto refuse = [](bool given, const char* option) {
        if (given) throw Error(std::string("dem: ") + option + " does not apply to --product");
    };
    refuse(o.from != "full", "--from overview");
    refuse(!o.method.empty(), "--method");
    refuse(o.radius.has_value(), "--radius");
    refuse(o.power.has_value(), "--power");
    refuse(!o.rgb.empty(), "--rgb");
    refuse(!o.returns.empty(), "--returns (the products choose their returns)");
    refuse(!o.intensity.empty(), "--intensity");
    if (!o.classes.empty()) r.product_options.dtm_classes = PointFilter::parse(o.classes, "", "");
    r.product_options.classes_given = !o.classes.empty();
    apply_ground(o, r);
    if (o.max_edge) {
        if (!(*o.max_edge > 0)) throw Error("dem: --max-edge with --product must be a positive number of metres");
        r.product_options.max_edge_m = *o.max_edge;
    }
}

}  // namespace

DemRequest dem_request(const DemOptions& o) {
    check_numbers(o);
    DemRequest r;
    r.output = o.output;
    r.rgb = o.rgb;
    r.hillshade = o.hillshade;
    r.texel_m = o.texel;
    if (o.bounds.size() == 4) r.area = Area{o.bounds[0], o.bounds[1], o.bounds[2], o.bounds[3]};
    r.source = dem_source_from_name(o.from);
    r.model = o.model;
    r.threads = o.threads ? o.threads : std::max(1u, std::thread::hardware_concurrency());
    r.contours_interval = o.contours.value_or(0);
    if (o.force) r.contour_line_limit = 0;
    if (!o.block.empty()) std::tie(r.block_index, r.block_count) = parse_block_piece(o.block);
    r.memory_budget = o.memory;
    if (!o.product.empty()) {
        apply_products(o, r);
        return r;
    }
    if (o.ground != "classes" || !o.ground_options.empty()) {
        throw Error("dem: --ground applies to --product dtm or chm");
    }
    r.method = dem_method_from_name(o.method.empty() ? (r.source == DemSource::Full ? "mean" : "linear") : o.method,
                                    r.source);
    r.filter = PointFilter::parse(o.classes, o.returns, o.intensity);
    if (r.source == DemSource::Overview && !r.filter.keeps_every_return()) {
        throw Error("dem: --returns applies to --from full only: chunk points have no reliable returns");
    }
    apply_method_parameters(o, r);
    return r;
}

DemPlan dem_plan(const dataset::Dataset& ds, const DemRequest& request, int count) {
    DemPlan plan;
    plan.grid = dem_grid(ds, request);
    plan.blocks = plan.grid.all_blocks().count();
    for (const auto& t : ds.tiles) plan.points += t.tile.header.point_count;
    const std::vector<double> points = block_point_estimates(ds, plan.grid);
    const std::vector<BlockRange> all = dem_block_pieces(ds, plan.grid, count);
    for (std::size_t i = 0; i < all.size(); ++i) {
        DemGrid piece = plan.grid;
        piece.selection = all[i];
        plan.pieces.push_back({static_cast<int>(i + 1), all[i], piece.window(), points_in(points, plan.grid, all[i]),
                               dem_memory_bytes(ds, piece, request)});
    }
    return plan;
}

}  // namespace lidarscout::raster
