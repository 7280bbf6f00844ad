// Area and volume inside a polygon drawn on measured points (the viewer's area tool): the
// polygon's horizontal area, the area of the surface the points describe inside it, and the
// volume above (cut) and below (fill) a base, the plane through the polygon's vertices (their
// heights, least squares) or a given height. The points inside are gridded at about their spacing
// with the same per-texel means as the DEMs (recon/texel_stats.hpp); a cell inside the polygon
// without points takes the mean of its measured neighbours, up to 3 cells from one (counted as
// filled; farther ones are unmeasured and left out); cells whose centre lies inside the polygon
// make up the surface.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>

namespace lidarscout::recon {

using Point3 = std::array<double, 3>;  // x, y, z in metres

struct AreaVolumeOptions {
    double cell_m = 0;  // grid cell side; 0: twice the points' mean spacing inside (coarser past 4 million cells)
    std::optional<double> base_height;  // a horizontal base; unset: the plane through the vertices
    // The points are those inside the polygon already, chosen by the caller's point test (the viewer's
    // area tool: clip's, in the dataset CRS's units), and are not tested again here.
    bool points_inside = false;
};

struct AreaVolume {
    double horizontal_area_m2 = 0;  // the polygon's (exact)
    double surface_area_m2 = 0;     // of the gridded surface inside
    double cut_m3 = 0, fill_m3 = 0;  // above and below the base
    double cell_m = 0;
    std::uint64_t points = 0;          // points inside the polygon
    std::uint64_t cells = 0;           // cells inside the polygon
    std::uint64_t cells_filled = 0;    // of which without points (their neighbours' mean)
    std::uint64_t cells_unmeasured = 0;  // left out: no measured cell near them
    std::array<double, 3> base_plane{};  // z = a + b x + c y
    std::string base;                 // "plane through the 5 vertices" or "height 12.00 m"
};

// Throws lidarscout::Error (stage "measure") for fewer than 3 vertices, a polygon without area, a
// given cell_m making more than 4 million cells,
// vertices on one line when the base is their plane, or no point inside the polygon.
AreaVolume measure_area_volume(std::span<const Point3> polygon, std::span<const Point3> points,
                               const AreaVolumeOptions& options = {});

// "area 400.0 m2 (surface 402.1 m2), cut 200.0 m3, fill 0.0 m3 over the plane through the 4 vertices; 1,600 points
// in 400 cells of 1.00 m (3 filled)".
std::string area_volume_summary(const AreaVolume& a);

}  // namespace lidarscout::recon
