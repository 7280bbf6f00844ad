// Finding the ground among unclassified points: the simple morphological filter (SMRF, Pingel,
// Vincent & Mitchell 2013, as PDAL's filters.smrf runs it) on a square lattice of cells.
//   0. cells as wide as the points' spacing where the points are sparser than one per cell;
//   1. the lowest point of each cell; empty cells filled (pull-push, hole_fill.hpp);
//   2. low outliers (pits deeper than a slope of 5 against their neighbours) left out;
//   3. the surface opened (erosion then dilation, square windows) with radii of 1 .. window / cell
//      cells: a cell whose height drops by more than slope x radius x cell at an opening stands on
//      an object (a roof, a tree), not on the ground; the slope, unless given, from the terrain
//      (the steepness between window-sized cells' lowest points; PDAL's 0.15 on gentle land);
//   4. the provisional ground surface: the lowest points of the other cells, holes filled;
//   5. a point is ground when it lies within threshold + scalar x local slope of that surface.
// Everything is local to the lattice it is given, so equal inputs give equal results: the DEM's
// blocks (raster/block_gridders.hpp) each run it on their own points and margin.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace lidarscout::recon {

// SMRF's parameters, PDAL's defaults but the slope (metres, slopes as rise over run).
struct GroundFilterParams {
    double cell_m = 1.0;       // the lattice's cell
    double slope = 0;          // the steepest terrain kept as ground; 0: from the terrain (at least 0.15)
    double window_m = 18.0;    // the largest opening's radius: about half the widest building
    double threshold_m = 0.5;  // the height above (or below) the provisional surface still ground
    double scalar = 1.25;      // how much the surface's local slope widens the threshold
};

// Throws lidarscout::Error naming `what` (e.g. "--ground-slope") for a parameter that is not a
// positive, finite number of sensible size.
void check_ground_params(const GroundFilterParams& p);

// The square lattice the filter runs on: `cells` x `cells` cells of `cell_m`, the south-west corner
// at (min_x, min_y).
struct GroundLattice {
    double min_x = 0, min_y = 0;
    double cell_m = 1.0;
    int cells = 0;
};

// A lattice covering a square of side `side_m` from (min_x, min_y), with cells of the params' size
// or larger, so that it has at most `max_cells` on a side.
GroundLattice ground_lattice(double min_x, double min_y, double side_m, const GroundFilterParams& p,
                             int max_cells = 2048);

// The openings' largest radius, in cells of `cell_m`.
int opening_radius_cells(const GroundFilterParams& p, double cell_m);
// How far from a cell the filter's verdict there looks, in metres, on cells of `cell_m`: the
// opening (an erosion and a dilation of the largest radius), the slopes and the sampling of the
// surface (a cell each).
double ground_filter_reach_m(const GroundFilterParams& p, double cell_m);

struct GroundSample {
    double x = 0, y = 0;
    float z = 0;  // any datum common to all samples (only differences matter)
};

// 1 for each sample found on the ground, 0 for the others (and for samples off the lattice). The
// lattice's cells grow to the samples' spacing where they are sparser (step 0).
std::vector<std::uint8_t> find_ground(std::span<const GroundSample> samples, const GroundLattice& lattice,
                                      const GroundFilterParams& p);

}  // namespace lidarscout::recon
