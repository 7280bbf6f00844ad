// Picking and measuring on what the viewer holds, without any window code: the point under a
// pixel (the front-most of the full-resolution LOD points and the overview's chunk points within
// a few pixels of it), its coordinates in the source file's own CRS units, and the distance and
// height difference between two picked points.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/point_filter.hpp"
#include "dataset/dataset.hpp"
#include "render/camera.hpp"
#include "viewer/scene_snapshot.hpp"

namespace lidarscout::viewer {

struct PickedPoint {
    double x = 0, y = 0, z = 0;  // world metres (as drawn)
    std::uint8_t r = 0, g = 0, b = 0;
    std::uint8_t classification = 0;
    std::uint16_t intensity = 0;
    std::optional<std::uint32_t> tile;  // the tile it came from (full-resolution points)
    bool chunk_point = false;           // an overview chunk point, not a full-resolution one
    bool surface = false;               // a heightmap's surface (surface_pick.hpp), not a measured point
    double pixel_distance = 0;          // from the picked pixel to the point's projection
    double depth = 0;                   // metres along the viewing direction
    std::optional<std::array<double, 2>> lonlat;  // degrees (WGS 84), filled by who knows the CRS
};

struct PickOptions {
    double radius_px = 4;        // how far from the pixel a point may be
    double lod_spacing_px = 0;   // LOD level searched (0: every point held, as a refined frame)
    bool chunk_points = true;    // also the chunk points of cells without a heightmap
    PointFilter filter;          // only the points it keeps, as they are the ones drawn
};

// The front-most point held by `snapshot` whose projection at `camera` lies within
// options.radius_px of pixel (px, py) (continuous pixel coordinates, row 0 at the top);
// nullopt when there is none.
std::optional<PickedPoint> pick_point(const SceneSnapshot& snapshot, const render::Camera& camera, double px,
                                      double py, const PickOptions& options = {});

// The tile a chunk point belongs to: the first tile whose bounds hold (x, y); nullopt if none.
std::optional<std::uint32_t> tile_at(const dataset::Dataset& dataset, double x, double y);

// A picked point in the file's own terms: x, y, z in its CRS units (world metres divided by the
// tile's unit factors), the unit names and the source file; for a tile reprojected into the
// dataset's CRS, x and y in that CRS's units (z stays in the file's vertical unit).
struct PointReadout {
    double x = 0, y = 0, z = 0;
    std::string horizontal_unit = "m", vertical_unit = "m";
    std::string crs;   // "EPSG:n", the CRS name, or "" when the file gives none
    std::string file;  // the tile's path ("" when unknown)
};
PointReadout point_readout(const dataset::Dataset& dataset, const PickedPoint& point);
// One line: "x X y Y z Z (UNIT, z in UNIT, CRS) [lon L lat B] class C (NAME) intensity I rgb R G B FILE";
// for a surface point "... heightmap surface (interpolated, not a measured point) rgb R G B FILE".
std::string point_summary(const dataset::Dataset& dataset, const PickedPoint& point);

struct Measurement {
    double distance_m = 0;    // straight line, 3D
    double horizontal_m = 0;  // in the xy plane
    double dz_m = 0;          // b.z - a.z
    double slope_deg = 0;     // of the line from a to b against the horizontal
};
Measurement measure(const PickedPoint& a, const PickedPoint& b);
// One line: "distance D m, horizontal H m, height difference +Z m, slope S deg".
std::string measurement_summary(const Measurement& m);

// What a click in the picture does: show the point under it, measure between two points, add a
// polygon's vertex, or give a profile's line (its two ends).
enum class ClickTool { Inspect, Measure, Area, Profile };

struct ClickState {
    ClickTool tool = ClickTool::Inspect;
    std::optional<PickedPoint> picked;  // Inspect: the last point clicked
    std::optional<PickedPoint> from;    // Measure, Profile: the first point
    std::optional<PickedPoint> to;      // Measure, Profile: the second point
    std::vector<PickedPoint> polygon;   // Area: the vertices clicked so far
    std::optional<std::string> area;    // Area: the last measurement's summary (or why it failed)
    bool missed = false;                // the last click found no point

    // A click's result: Inspect keeps the point; Measure and Profile fill the first point, then the
    // second, then start again from the next one; Area adds a vertex (after a measurement, a new polygon).
    // A miss changes nothing but `missed`.
    void clicked(const std::optional<PickedPoint>& point);
    // Switches the tool, forgetting what the other one picked.
    void use(ClickTool next);
};

}  // namespace lidarscout::viewer
