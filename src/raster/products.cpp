// The products of `dem --product`: their names, files, layers and values.
#include "raster/products.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "core/error.hpp"

namespace lidarscout::raster {

namespace {

constexpr std::pair<Product, std::string_view> kProductNames[] = {
    {Product::Dtm, "dtm"},         {Product::Dsm, "dsm"},
    {Product::Chm, "chm"},         {Product::Density, "density"},
    {Product::PulseDensity, "pulse-density"}, {Product::Intensity, "intensity"},
    {Product::Count, "count"}};

constexpr std::uint8_t kNoiseClasses[] = {7, 18};  // low and high noise

// Every point but noise, of the return kinds `kinds`.
PointFilter without_noise(std::uint8_t kinds) {
    PointFilter f;
    for (const std::uint8_t c : kNoiseClasses) f.classes.reset(c);
    f.return_kinds = kinds;
    return f;
}

GridderSpec counting() {
    GridderSpec g;
    g.value = GridValue::Count;
    return g;
}

// The ground filter runs in each TIN block on the block and its margin: its openings (reaching
// twice the window) must stay within the widest margin (tin_margin_texels) for blocks to agree near
// their edges, and bound its work.
void check_ground_reach(const recon::GroundFilterParams& ground, double texel_m) {
    recon::check_ground_params(ground);
    const double most = kMaxTinMarginTexels * texel_m / 2;
    if (ground.window_m > most) {
        char text[200];
        std::snprintf(text, sizeof text,
                      "--ground-window %g m is more than half the %d-texel margin a block sees at --texel %g "
                      "(%g m): give a larger --texel or a smaller window",
                      ground.window_m, kMaxTinMarginTexels, texel_m, most);
        throw Error::in_stage("dem", text);
    }
}

}  // namespace

std::vector<Product> products_from_names(std::string_view list) {
    std::vector<Product> out;
    std::size_t start = 0;
    while (start <= list.size()) {
        const std::size_t comma = std::min(list.find(',', start), list.size());
        const std::string_view name = list.substr(start, comma - start);
        const auto it = std::find_if(std::begin(kProductNames), std::end(kProductNames),
                                     [&](const auto& p) { return p.second == name; });
        if (it == std::end(kProductNames)) {
            throw Error("--product: unknown product '" + std::string(name) +
                        "' (dtm, dsm, chm, density, pulse-density, intensity, count, separated by commas)");
        }
        if (std::find(out.begin(), out.end(), it->first) != out.end()) {
            throw Error("--product: " + std::string(name) + " is named twice");
        }
        out.push_back(it->first);
        start = comma + 1;
    }
    return out;
}

std::string_view product_name(Product product) {
    for (const auto& [p, n] : kProductNames) {
        if (p == product) return n;
    }
    return "?";
}

bool is_height_product(Product p) { return p == Product::Dtm || p == Product::Dsm || p == Product::Chm; }

std::vector<std::string> product_paths(const std::string& output, std::span<const Product> products) {
    if (products.size() == 1) return {output};
    const std::filesystem::path path(output);
    std::vector<std::string> out;
    for (const Product p : products) {
        std::filesystem::path named = path;
        named.replace_filename(path.stem().string() + "_" + std::string(product_name(p)) + path.extension().string());
        out.push_back(named.string());
    }
    return out;
}

ProductPass::ProductPass(std::span<const Product> products, const ProductOptions& options, double texel_m)
    : texel_m_(texel_m),
      max_edge_m_(options.max_edge_m > 0 ? options.max_edge_m : kDefaultProductMaxEdgeTexels * texel_m) {
    const auto wants = [&](std::initializer_list<Product> any) {
        return std::any_of(products.begin(), products.end(),
                           [&](Product p) { return std::find(any.begin(), any.end(), p) != any.end(); });
    };
    const auto add = [&](const GridderSpec& g, const PointFilter& f) {
        layers_.push_back({g, f});
        return static_cast<int>(layers_.size()) - 1;
    };
    GridderSpec tin;
    tin.method = GridMethod::Tin;
    tin.tin_max_edge_m = max_edge_m_;
    if (options.ground) check_ground_reach(*options.ground, texel_m);
    if (wants({Product::Dtm, Product::Chm})) {
        GridderSpec dtm = tin;
        dtm.ground = options.ground;
        const bool all = options.ground && !options.classes_given;
        dtm_ = add(dtm, all ? without_noise(returns::kAny) : options.dtm_classes);
    }
    if (wants({Product::Dsm, Product::Chm})) {
        GridderSpec highest = tin;
        highest.method = GridMethod::HighestTin;
        dsm_ = add(highest, without_noise(returns::kFirst));
    }
    if (wants({Product::Density, Product::Count})) all_ = add(counting(), without_noise(returns::kAny));
    if (wants({Product::PulseDensity})) first_ = add(counting(), without_noise(returns::kFirst));
    if (wants({Product::Intensity})) {
        GridderSpec mean;
        mean.value = GridValue::Intensity;
        intensity_ = add(mean, without_noise(returns::kAny));
    }
}

int ProductPass::block_texels() const {
    int margin = 0;
    for (const GridLayer& l : layers_) margin = std::max(margin, tin_margin_texels(l.gridder, texel_m_));
    return tin_block_texels(margin);
}

int ProductPass::layer_of(Product p) const {
    switch (p) {
    case Product::Dtm: return dtm_;
    case Product::Dsm:
    case Product::Chm: return dsm_;
    case Product::Density:
    case Product::Count: return all_;
    case Product::PulseDensity: return first_;
    case Product::Intensity: return intensity_;
    }
    return -1;
}

std::vector<float> ProductPass::values(Product p, std::span<const BlockImages> layers, double z_to_metres,
                                       float nodata) const {
    const int layer = layer_of(p);
    if (layer < 0 || static_cast<std::size_t>(layer) >= layers.size()) {
        throw Error::in_stage("dem", "a product without its layer (internal error)");
    }
    const std::vector<float>& v = layers[static_cast<std::size_t>(layer)].heights_m;
    switch (p) {
    case Product::Dtm:
    case Product::Dsm: return heights_in_file_units(v, z_to_metres, nodata);
    case Product::Chm: {
        // From the dsm and dtm as their files hold them, so that chm = dsm - dtm there exactly.
        std::vector<float> out = heights_in_file_units(v, z_to_metres, nodata);
        const std::vector<float> dtm = heights_in_file_units(layers[dtm_].heights_m, z_to_metres, nodata);
        for (std::size_t i = 0; i < out.size(); ++i) {
            out[i] = out[i] == nodata || dtm[i] == nodata ? nodata : std::max(0.0f, out[i] - dtm[i]);
        }
        return out;
    }
    case Product::Density:
    case Product::PulseDensity: {
        const double area = texel_m_ * texel_m_;
        std::vector<float> out(v.size());
        for (std::size_t i = 0; i < v.size(); ++i) out[i] = static_cast<float>(v[i] / area);
        return out;
    }
    case Product::Count: return v;
    case Product::Intensity: return heights_in_file_units(v, 1.0, nodata);
    }
    return {};
}

void ProductPass::check_points(std::span<const Product> products, std::span<const std::uint64_t> layer_points,
                               std::uint64_t points_read) const {
    const auto empty = [&](int layer) {
        return layer >= 0 && static_cast<std::size_t>(layer) < layer_points.size() && layer_points[layer] == 0;
    };
    for (const Product p : products) {
        std::string what;
        if (empty(p == Product::Dsm ? -1 : layer_of(p == Product::Chm ? Product::Dtm : p))) {
            what = p == Product::Dtm || p == Product::Chm ? "of the dtm's classes " + layers_[dtm_].filter.class_list()
                   : p == Product::PulseDensity          ? "that is a first return (noise left out)"
                                                         : "but noise";
        } else if ((p == Product::Dsm || p == Product::Chm) && empty(dsm_)) {
            what = "that is a first return (noise left out)";
        } else {
            continue;
        }
        throw Error::in_stage("dem", "no point " + what + " lies in the area (" + std::to_string(points_read) +
                                         " points read), so the " + std::string(product_name(p)) +
                                         " would be empty; nothing written" +
                                         (p == Product::Dtm || p == Product::Chm
                                              ? ": give --classes, or --ground smrf to find the ground among "
                                                "unclassified points"
                                              : ""));
    }
}

RasterLayout ProductPass::layout(Product p, const std::string& height_unit, float nodata) const {
    RasterLayout l;
    l.nodata = nodata;
    switch (p) {
    case Product::Dtm: l.description = "elevation (terrain)"; break;
    case Product::Dsm: l.description = "elevation (surface)"; break;
    case Product::Chm: l.description = "canopy height"; break;
    case Product::Density: l.description = "points per square metre"; break;
    case Product::PulseDensity: l.description = "first returns per square metre"; break;
    case Product::Intensity: l.description = "mean intensity"; break;
    case Product::Count: l.description = "points per texel"; break;
    }
    if (is_height_product(p)) l.unit = height_unit;
    return l;
}

}  // namespace lidarscout::raster
