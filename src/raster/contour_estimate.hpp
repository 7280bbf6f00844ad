// How many contour lines (and points) GDAL's contour generator would draw from a height raster, counted
// in one pass over the raster before it draws any, for several intervals at once: so that `dem
// --contours` refuses an interval that would write millions of lines (and suggests one that does not),
// and prices the contours' memory before the work.
//
// Points: every level a texel edge spans is one crossing, one point of a line (plus the closing
// point of a ring). Lines: on a raster without holes, the contour lines of one level part the raster
// into regions that form a tree (each line has a region on either side), so the lines of a level are
// the regions above it plus those below it, less one. How many regions stand above a level follows
// from the heights' persistence pairs (each local maximum's component lives from its height down to
// the saddle where it joins a higher one), found by one union-find sweep down the sorted texels
// (8-connected) and, for the regions below, one sweep up (4-connected, the dual). On the shared
// surveys the counts are within 15% of GDAL's (tests/raster/contour_estimate_test.cpp); nodata holes
// and the seams between the blocks a large raster is counted in make them approximate.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace lidarscout::raster {

struct ContourCount {
    double interval = 0;
    double lines = 0;     // line strings, one feature each
    double vertices = 0;  // their points
};

// The counts for each of `intervals` (positive) of the width x height texels at `values` (rows
// `stride` floats apart), texels equal to `nodata` or not finite left out.
std::vector<ContourCount> count_contours(const float* values, int width, int height, std::ptrdiff_t stride,
                                         float nodata, std::span<const double> intervals);

// The same for band 1 of the raster at `path` (nodata `nodata`), read in blocks of at most
// kContourBlock x kContourBlock texels, counted apart and joined by the lines that cross their seams.
// Throws lidarscout::Error naming the file when it cannot be read.
inline constexpr int kContourBlock = 1024;
std::vector<ContourCount> count_contours(const std::string& path, double nodata, std::span<const double> intervals);

// `interval`, then the intervals of 1, 2 or 5 times a power of ten above it, `coarser` of them: those to
// try when `interval` draws too much.
std::vector<double> contour_intervals(double interval, int coarser = 24);

// The memory GDAL's contour generator may hold at once for `count` of a raster of `texels` float
// texels: the program, the raster's blocks it reads (at most GDAL's block cache) and every point of every line
// (a line stays open until the generator's sweep leaves it, and lines as tall as the raster all
// stay open: 33 bytes a point were measured on such a raster with GDAL 3.6, 13 on the Woodford
// tile's mean DEM at 0.0025 ft), at 40 bytes a point.
std::uint64_t contour_memory_bytes(const ContourCount& count, double texels);

}  // namespace lidarscout::raster
