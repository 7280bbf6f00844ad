// How one block of a DEM made from every point turns the points it receives into heights and
// colours (`lidarscout dem --from full --method ...`):
//   mean, min, max  each point goes to the texel it falls in (recon/texel_stats.hpp, the same
//                   gridding as eval's ground truth); the texel's statistic
//   idw             each point goes to every texel whose centre lies within `idw_radius_m`:
//                   the texel is the inverse-distance weighted mean (weights 1 / d^power) of
//                   those points, nodata where none (as gdal_grid -a invdist with a radius,
//                   PDAL writers.gdal output_type idw)
//   tin             the block's points and those of a margin around it (with `ground`, those of
//                   them the ground filter finds) are triangulated
//                   (Delaunay, recon/triangulation.hpp) and each texel centre is interpolated
//                   linearly in its triangle (as gdal_grid -a linear, LAStools las2dem);
//                   nodata outside the hull and in triangles with an edge longer than
//                   `tin_max_edge_m` (0: no limit)
//   highest-tin     the highest point of each texel (of the block and its margin); texels without
//                   one get the TIN of those highest points, as tin does (a DSM: holes up to
//                   the maximum edge filled)
// A tin finds each texel's triangle (TinSearch) by a walk over the Delaunay triangles near the
// texel's centre, built one at a time from the points around it (recon/local_delaunay.hpp: exact,
// no triangulation of every point), or triangulates every point (CGAL). Both give the same
// triangles; by default the walk where points are dense enough.
// mean, min, max can also grid the points' intensity, or count them (GridValue).
// A block receives every point within reach of it (gridder_reach_m), so blocks meet without
// seams: texels near a border see the same points whichever block holds them. For tin this
// holds where the triangles' circumcircles fit in the margin (everywhere the points are denser than
// the margin is wide; gaps wider than it, like lakes, may triangulate differently per block).
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "dataset/point_stream.hpp"
#include "raster/dem_grid.hpp"
#include "recon/ground_filter.hpp"
#include "recon/texel_stats.hpp"

namespace lidarscout::raster {

enum class GridMethod { Statistic, Idw, Tin, HighestTin };
// What a Statistic gridder makes of a texel's points: their height's statistic, their intensity's
// statistic, or their number (0, not NaN, where none).
enum class GridValue { Height, Intensity, Count };
// How a tin finds the triangle over each texel centre: Auto (Local from 0.5 points per texel on,
// and for highest-tin's holes; else Triangulate), Local, Triangulate.
enum class TinSearch { Auto, Local, Triangulate };

// How the thinned walks of tin blocks went (GridderSpec::thinning_tally): blocks that thinned, and
// their texels proven by the first walk, by the later ones, and left to the walk over every point.
struct TinThinningTally {
    std::atomic<std::uint64_t> blocks{0}, first{0}, later{0}, whole{0};
};

struct GridderSpec {
    GridMethod method = GridMethod::Statistic;
    recon::TexelStatistic statistic = recon::TexelStatistic::Mean;  // for Statistic
    GridValue value = GridValue::Height;                            // for Statistic
    double idw_radius_m = 0;    // for Idw; 0: the texel's diagonal (texel x sqrt 2)
    double idw_power = 2;       // for Idw
    double tin_max_edge_m = 0;  // for Tin and HighestTin; 0: no limit
    // For Tin: triangulate only the points the ground filter finds among those received (run on
    // the block and its margin, recon/ground_filter.hpp).
    std::optional<recon::GroundFilterParams> ground;
    bool rgb = false;           // also grid the colours
    TinSearch tin_search = TinSearch::Auto;  // for Tin and HighestTin
    // For Tin with an edge limit: a block with kTinThinFromPointsPerTexel points a texel and more walks
    // over the points near its texel centres first, keeping only the answers proven to be the whole
    // set's (the same triangles; heights equal within float rounding); false: over every point.
    bool tin_thinning = true;
    TinThinningTally* thinning_tally = nullptr;  // where to count how thinning went (tests, benchmarks)
};

// The margin (texels on each side) a tin block sees beyond its own texels is what its gridder
// reaches (tin_margin_texels), at most kMaxTinMarginTexels; the block and its margins fit in recon's
// exact window (kTinWindowTexels), so the blocks of a pass are that window less twice the widest
// margin among its layers (tin_block_texels).
inline constexpr int kMaxTinMarginTexels = 64;
inline constexpr int kTinWindowTexels = 512;
// From this many points per texel of a tin block and its margin on, TinSearch::Auto walks to each
// texel's triangle: on ky-jmo335 about as fast as CGAL's triangulation at 0.65 points per texel,
// faster above (3x at 16 and more).
inline constexpr double kTinWalkPointsPerTexel = 0.5;
// From this many points per texel of a tin block and its margin on, the walk is thinned
// (GridderSpec::tin_thinning).
inline constexpr double kTinThinFromPointsPerTexel = 24;

// The margin of a Tin or HighestTin block (0 for the others): its longest edge and, with the ground
// filter, the filter's reach on the block's lattice (recon::ground_filter_reach_m), plus 4 texels;
// kMaxTinMarginTexels without an edge limit and at most that. Every point of a margin is filtered,
// sorted and bucketed again by each block that sees it: on ky-jmo335 at 1 m the three products with
// the ground filter took 8.5-8.8 s with margins of 40 against 10.3 s with the 64 texels every tin had
// before (one run each, the same hour).
int tin_margin_texels(const GridderSpec& spec, double texel_m);
// The blocks of a pass whose widest tin margin is `margin` (512 without a tin).
int tin_block_texels(int margin);

// The ground filter's lattice for a tin block whose south-west corner is (block_min_x, block_min_y):
// the block and its margin of `margin` texels.
recon::GroundLattice tin_ground_lattice(const DemGrid& grid, int margin, double block_min_x, double block_min_y,
                                        const recon::GroundFilterParams& params);

// How far (metres) from a block a point still changes it.
double gridder_reach_m(const GridderSpec& spec, double texel_m);

// A finished block: heights in metres (NaN where none; for GridValue Intensity or Count, that
// value), block x block texels, rows from the south; with colour, RGBA planes (4 x block x block
// bytes; alpha 255 where a height is).
struct BlockImages {
    std::vector<float> heights_m;
    std::vector<std::uint8_t> rgba;
};

class BlockGridder {
public:
    virtual ~BlockGridder() = default;
    // A point within reach of the block; `own` is its texel when it falls inside this block.
    virtual void add(const dataset::MetricPoint& point, const recon::TexelLocation* own) = 0;
    // The same with the point's texel in the grid's lattice (`at`, whichever block it falls in) already
    // located, for gridders that want it for points of other blocks too.
    virtual void add_located(const dataset::MetricPoint& point, const recon::TexelLocation* own,
                             const recon::TexelLocation& at) {
        add(point, own);
    }
    virtual BlockImages finish() = 0;
    // The points it holds until it is finished (a tin block's; the others hold texels only).
    virtual std::uint64_t held_points() const { return 0; }
};

// The gridder of block `block` of `grid`. Throws Error for a spec that does not fit (a radius
// or power that is not positive, a tin grid whose blocks leave no room for the margin).
std::unique_ptr<BlockGridder> make_block_gridder(const GridderSpec& spec, const DemGrid& grid, CellKey block);

}  // namespace lidarscout::raster
