// Areas on the ground (clip, the viewer's area tool): polygons with holes and multipolygons in the
// dataset CRS's units (plain planar geometry, no PROJ), with an even-odd point-in-polygon test that
// is exact on edges (a point on an edge or vertex is inside), and their strict parsing from WKT
// (POLYGON / MULTIPOLYGON) and GeoJSON (a Polygon or MultiPolygon geometry, Feature or
// FeatureCollection of them).
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace lidarscout {

struct XY {
    double x = 0, y = 0;
    bool operator==(const XY&) const = default;
};

// A closed ring (the last vertex joins the first; a repeated closing vertex is dropped).
using Ring = std::vector<XY>;

// Polygons, each an outer ring followed by its holes. A point is inside when it lies on a ring's
// edge or crosses an odd number of ring edges: holes cut out, disjoint parts add up.
class MultiPolygon {
public:
    MultiPolygon() = default;
    // Throws lidarscout::Error (stage "polygon") for a ring of fewer than 3 distinct vertices or a
    // vertex that is not finite.
    explicit MultiPolygon(std::vector<std::vector<Ring>> polygons);

    bool contains(double x, double y) const;
    // Whether the polygon and the box [min_x, max_x] x [min_y, max_y] share a point (edges count).
    bool touches_box(double min_x, double min_y, double max_x, double max_y) const;
    // The box around every vertex: min_x, min_y, max_x, max_y.
    double min_x() const { return min_x_; }
    double min_y() const { return min_y_; }
    double max_x() const { return max_x_; }
    double max_y() const { return max_y_; }
    // Horizontal area (outer rings minus holes).
    double area() const;
    const std::vector<std::vector<Ring>>& polygons() const { return polygons_; }

private:
    std::vector<std::vector<Ring>> polygons_;
    double min_x_ = 0, min_y_ = 0, max_x_ = 0, max_y_ = 0;
};

// "POLYGON ((x y, ...), (hole...))" or "MULTIPOLYGON (((...)), ((...)))", case-insensitive, an
// optional Z or M ordinate ignored. Throws lidarscout::Error naming what was expected and where.
MultiPolygon parse_wkt_polygon(std::string_view text);

// A GeoJSON document: a Polygon or MultiPolygon geometry, or a Feature / FeatureCollection whose
// geometries are (all of them are joined), read by the bounded JSON reader (core/json_reader.hpp;
// at most 5 million vertices, kept as rings only). Throws lidarscout::Error naming what is wrong.
MultiPolygon parse_geojson_polygon(std::string_view text);

// The polygon of a --polygon argument: WKT when it starts with POLYGON or MULTIPOLYGON, else
// the path of a GeoJSON file. Throws lidarscout::Error.
MultiPolygon read_polygon_argument(const std::string& argument);

}  // namespace lidarscout
