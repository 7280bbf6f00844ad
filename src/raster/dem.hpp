// `lidarscout dem` as a library call: the DEM of a dataset as a float32 Cloud-Optimized
// GeoTIFF in the dataset's CRS (its native units, nodata -9999), optionally its orthophoto
// (RGBA COG of the mean point colours), a hillshade PNG and contour lines (GeoPackage).
//   from full:      every point, per texel the mean, min or max height, or inverse distance
//                   weighting, or a TIN (full_dem.hpp, block_gridders.hpp)
//   from overview:  the chunk points only, per 64-texel patch the linear interpolation or the
//                   heightmap network (overview_dem.hpp)
//   products:       from every point, several rasters in one read (dtm, dsm, chm, density,
//                   pulse-density, intensity, count; products.hpp)
// Any of the --from full rasters may be made in pieces that mosaic exactly (DemRequest::block_count).
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/error.hpp"
#include "raster/dem_grid.hpp"
#include "raster/full_dem.hpp"
#include "raster/products.hpp"

namespace lidarscout::dataset {
struct Dataset;
}

namespace lidarscout::raster {

enum class DemSource { Full, Overview };
enum class DemMethod { Mean, Min, Max, Idw, Tin, Linear, Cnn };

// "mean", "min", "max", "idw", "tin" (full), "linear", "cnn" (overview); throws Error for other names or a
// method that does not fit the source.
DemMethod dem_method_from_name(std::string_view name, DemSource source);
DemSource dem_source_from_name(std::string_view name);
std::string_view dem_method_name(DemMethod method);

// Called as work advances: (stage, done, total); stages "points", "patches", "cog".
using DemProgressFn = std::function<void(std::string_view stage, std::uint64_t done, std::uint64_t total)>;

// 200,000 lines: GDAL's generator and GeoPackage wrote about 25,000 a second (with 16 points each) on the
// Woodford tile, where `--contours 0.01` ran 90 s for 2.27 M lines and 1.0 GB.
inline constexpr std::uint64_t kContourLineLimit = 200'000;

struct DemRequest {
    std::string output;     // the DEM (.tif)
    std::string rgb;        // the orthophoto (.tif), empty for none
    std::string hillshade;  // the hillshade (.png), empty for none
    double texel_m = 1.0;
    std::optional<Area> area;  // in the dataset's CRS units (not metres); empty: the whole dataset
    DemSource source = DemSource::Full;
    DemMethod method = DemMethod::Mean;
    PointFilter filter;  // every point by default (overview: returns are not known, only class and intensity)
    double idw_radius_m = 0;   // idw: search radius around each texel centre (0: the texel's diagonal)
    double idw_power = 2;      // idw: weights 1 / distance^power
    double tin_max_edge_m = 0; // tin: no height in triangles with a longer edge (0: no limit)
    std::string model;         // the network for cnn; empty: the shipped one
    // Products (from full only): when given, these instead of one DEM by `method`, all in one read
    // of the points, written to product_paths(output, products); `filter` is then not used.
    std::vector<Product> products;
    ProductOptions product_options;
    // Contour lines every this many height units (0: none) of the DEM, or of the first height
    // product, to contours_path() of that raster (contours.hpp).
    double contours_interval = 0;
    // Contours counted (contour_estimate.hpp) at more than this many lines are refused before GDAL
    // draws them, with an interval that stays under it (0: no limit, `--force`).
    std::uint64_t contour_line_limit = kContourLineLimit;
    // `dem --block I/N` (block_count 0: the whole DEM): only piece block_index (1-based) of the
    // grid's blocks cut in block_count (dem_blocks.hpp), written as a raster of that rectangle on
    // the whole grid's lattice; an empty piece is a raster of nodata, not an error. --from full only;
    // no hillshade or contours (they need the neighbours: make them from the mosaic).
    int block_index = 0, block_count = 0;
    unsigned threads = 1;
    // Bytes the DEM may hold at once (0: half of what the process may use, usable_memory_bytes()).
    // A DEM estimated to need more is refused before anything is allocated (dem_memory_bytes).
    std::uint64_t memory_budget = 0;
    DemProgressFn progress;
};

struct DemResult {
    DemGrid grid;
    std::vector<std::string> outputs;  // the rasters written (the DEM, or each product's)
    std::string contours;              // the contours' GeoPackage, empty for none
    std::uint64_t contour_lines = 0;
    double contour_lines_estimate = 0, contour_points_estimate = 0;  // counted before they were drawn
    std::uint64_t points_read = 0, points_used = 0;
    std::vector<ErrorRecord> skipped;  // chunks or tiles left out (unreadable), the DEM made without them
    std::uint64_t points_skipped = 0;
    std::size_t blocks_written = 0, peak_blocks = 0;
    std::uint64_t peak_held_points = 0;  // FullDemStats::peak_held_points
    std::uint64_t memory_estimate = 0, memory_budget = 0;  // bytes (dem_memory_bytes; the budget applied)
    double seconds_grid = 0, seconds_cog = 0, seconds_hillshade = 0, seconds_contours = 0;
};

// The memory the DEM of `grid` needs at once, estimated: for --from full the blocks in flight
// (full_dem_peak_bytes), for both the rasters' tile indexes (GDAL keeps two 8-byte offsets per
// 512 x 512 tile and band group, in the scratch raster and in the COG). The contours are priced
// when the height raster is made (their lines depend on its heights: contour_memory_bytes), and
// DemResult::memory_estimate is then the larger of the two.
std::uint64_t dem_memory_bytes(const dataset::Dataset& dataset, const DemGrid& grid, const DemRequest& request);

// The raster contours are drawn from: the DEM, or the first height product (empty when none).
std::string contour_source(const DemRequest& request);

// The grid make_dem makes `request`'s rasters on (the whole grid, no piece selected): the request's
// area (or the dataset's bounds) at its texel, in blocks of the size its method needs.
DemGrid dem_grid(const dataset::Dataset& dataset, const DemRequest& request);

// How far from the request's area (metres) a tile's points may still be used by make_dem of the full
// points (a block's width beyond the area's edge, and the widest gridder's reach beyond that, taken twice
// over): a tile farther from the area changes nothing written. A caller that reads only the tiles
// within it (dataset::keep_tiles_touching) writes the same rasters.
double dem_reach_m(const DemRequest& request);

// Throws Error for a method that does not fit the source, a raster far larger than the tiles
// cover, or one whose memory estimate exceeds the budget (naming the size and the way out:
// a larger --texel, or --bounds); and, once the height raster is made, for contours counted at
// more lines than contour_line_limit or more memory than the budget (naming an interval that fits).
// Every file of the request (rasters, hillshade and its sidecars, contours) is written under a
// temporary name and all are renamed together at the end (io/output_group.hpp): an error or Ctrl-C
// leaves none of them, and the files they would replace untouched.
DemResult make_dem(const dataset::Dataset& dataset, const DemRequest& request);

}  // namespace lidarscout::raster
