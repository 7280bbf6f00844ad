// The products of `lidarscout dem --product`, made together in one read of the points: each is
// a raster computed from a few layers (full_dem.hpp's GridLayer: the points a filter keeps, gridded
// one way) that products share:
//   dtm            TIN of the ground and water points (DTM classes, default 2,9), nodata in
//                  triangles with an edge longer than the maximum edge (as `--method tin`); with
//                  the ground filter (`--ground smrf`), TIN of the points it finds on the ground
//   dsm            the highest first return per texel; texels without one get the TIN of those
//                  highest points within the maximum edge (block_gridders.hpp's highest-tin)
//   chm            dsm - dtm, clamped at 0, where both are (in the file's unit)
//   density        points per square metre of each texel
//   pulse-density  first returns per square metre
//   intensity      the mean intensity of the texel's points (nodata where none)
//   count          points per texel
// Noise (classes 7 and 18) is left out of every product but a dtm whose classes name it; density
// and count are 0, not nodata, where no point fell.
#pragma once

#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/point_filter.hpp"
#include "raster/block_raster.hpp"
#include "raster/full_dem.hpp"
#include "recon/ground_filter.hpp"

namespace lidarscout::raster {

enum class Product { Dtm, Dsm, Chm, Density, PulseDensity, Intensity, Count };

// "dtm,dsm,chm" in that order; throws Error for an unknown, repeated or missing name.
std::vector<Product> products_from_names(std::string_view list);
std::string_view product_name(Product product);
bool is_height_product(Product product);  // dtm, dsm, chm

// Where each product is written: `output` itself for one product; for several, `output` with
// "_NAME" before its extension (out.tif -> out_dtm.tif, out_dsm.tif).
std::vector<std::string> product_paths(const std::string& output, std::span<const Product> products);

// The maximum edge of dtm and dsm when none is given: 20 texels.
inline constexpr double kDefaultProductMaxEdgeTexels = 20;

struct ProductOptions {
    PointFilter dtm_classes = PointFilter::parse("2,9", "", "");  // the points of the dtm's TIN
    double max_edge_m = 0;                                        // 0: kDefaultProductMaxEdgeTexels texels
    // Set: the dtm is the TIN of the points the ground filter finds among every point but noise
    // (or among `dtm_classes` when `classes_given`), for surveys without a ground class.
    std::optional<recon::GroundFilterParams> ground;
    bool classes_given = false;
};

// The layers a set of products needs, and each product's values from a finished block's layers.
class ProductPass {
public:
    ProductPass(std::span<const Product> products, const ProductOptions& options, double texel_m);

    std::span<const GridLayer> layers() const { return layers_; }
    int block_texels() const;   // the pass's blocks: room for its widest tin margin
    double max_edge_m() const { return max_edge_m_; }

    // Product `p`'s block in the file's units (heights / z_to_metres), `nodata` where none.
    std::vector<float> values(Product p, std::span<const BlockImages> layers, double z_to_metres,
                              float nodata) const;

    // Throws Error (nothing is written) when a product's layers got no point (`layer_points`, per
    // layer): no silent empty product, e.g. a dtm of a survey without ground classes.
    void check_points(std::span<const Product> products, std::span<const std::uint64_t> layer_points,
                      std::uint64_t points_read) const;

    // The band's unit and description for product `p` (heights in `height_unit`).
    RasterLayout layout(Product p, const std::string& height_unit, float nodata) const;

private:
    int layer_of(Product p) const;  // the layer a product reads (for chm: the dsm's)

    double texel_m_, max_edge_m_;
    std::vector<GridLayer> layers_;
    int dtm_ = -1, dsm_ = -1, all_ = -1, first_ = -1, intensity_ = -1;
};

}  // namespace lidarscout::raster
