// Areas on the ground (clip, the viewer's area tool): polygons with holes and multipolygons in the
// dataset CRS's units (plain planar geometry, no PROJ), with a point-in-polygon test that is exact on
// edges (a point on an edge or vertex is inside) and goes through an index of the edges by rows, and
// their strict parsing from WKT (POLYGON / MULTIPOLYGON) and GeoJSON (a Polygon or MultiPolygon
// geometry, Feature or FeatureCollection of them).
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <span>
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

// Polygons, each an outer ring followed by its holes; the region is the union of the polygons. A
// point is inside a polygon when it lies on an edge of one of its rings or crosses an odd number of
// them (even-odd: a polygon's holes cut that polygon only); it is inside the MultiPolygon when it is
// inside any of its polygons, so overlapping parts add up and another part's hole stays covered.
//
// The test goes through an index built once by the constructor: the y-range cut into bands (rows),
// each listing the edges whose y-range meets it, so a point examines the edges of its band only: about
// the edges a horizontal line crosses there plus edges / bands, not every edge (an outline: a few; a
// star of 100k thin spikes: tens of thousands). The band count is at most the edge count and chosen so
// that edges spanning many bands (a star's spikes, a spiral) leave the index at most about 4 entries
// per edge; the memory is linear in the vertices (about 32 bytes a vertex with the vertices).
class MultiPolygon {
public:
    MultiPolygon() = default;
    // Throws lidarscout::Error (stage "polygon") for a ring of fewer than 3 distinct vertices, a vertex
    // that is not finite, or more vertices than the index can name (hundreds of millions).
    explicit MultiPolygon(std::vector<std::vector<Ring>> polygons);

    bool contains(double x, double y) const;
    // Whether the polygon and the box [min_x, max_x] x [min_y, max_y] share a point (edges count).
    bool touches_box(double min_x, double min_y, double max_x, double max_y) const;
    // The box around every vertex: min_x, min_y, max_x, max_y.
    double min_x() const { return min_x_; }
    double min_y() const { return min_y_; }
    double max_x() const { return max_x_; }
    double max_y() const { return max_y_; }
    // Horizontal area: the sum over the polygons of the outer ring's area minus its holes' (at least
    // zero). That is the union's area when the polygons do not overlap, their rings do not cross and
    // their holes lie inside their outer ring; an overlap counts once per polygon covering it (an exact
    // union would need polygon clipping, CGAL's, which core does not link). Its users measure one drawn
    // ring (recon's area tool) or a square (bench_region).
    double area() const;
    std::size_t polygon_count() const { return polygon_starts_.empty() ? 0 : polygon_starts_.size() - 1; }
    // Vertices over all rings (a ring's repeated closing vertex not counted).
    std::size_t vertex_count() const;

    // The rings, for checks of the shape (core/polygon_validity.hpp): the polygons' rings in order (each
    // polygon's outer ring first), ring r's vertices (without its closing vertex again) and the first
    // ring (the outer one) of polygon p.
    std::size_t ring_count() const { return ring_starts_.empty() ? 0 : ring_starts_.size() - 1; }
    std::span<const XY> ring(std::size_t r) const {
        return {vertices_.data() + ring_starts_[r], ring_starts_[r + 1] - ring_starts_[r] - 1};
    }
    std::size_t first_ring_of_polygon(std::size_t p) const {
        return std::lower_bound(ring_starts_.begin(), ring_starts_.end(), polygon_starts_[p]) - ring_starts_.begin();
    }

    // The work of the index, for tests and benchmarks: the edges contains(x, y) examines, and the
    // entries (edge references) the index holds over all its bands.
    std::size_t edges_examined(double x, double y) const;
    std::size_t index_entries() const { return band_edges_.size(); }
    // Bytes the polygon holds: its vertices and its index.
    std::size_t held_bytes() const;

private:
    void build_index();
    bool in_box(double x, double y) const { return x >= min_x_ && x <= max_x_ && y >= min_y_ && y <= max_y_; }
    std::size_t band_of(double y) const;
    std::span<const std::uint32_t> band(std::size_t b) const;

    // Every ring's vertices, each ring followed by its first vertex again: an edge is named by its
    // first vertex i and ends at i + 1.
    std::vector<XY> vertices_;
    std::vector<std::uint32_t> ring_starts_;     // where each ring starts in vertices_, then the end
    std::vector<std::uint32_t> polygon_starts_;  // where each polygon (its outer ring) starts, then the end
    // Band b lists the edges band_edges_[band_starts_[b] .. band_starts_[b + 1]) in ascending order,
    // so grouped by polygon; a y value's band is floor((y - min_y) * band_scale_), clamped.
    std::vector<std::uint32_t> band_starts_, band_edges_;
    double band_scale_ = 0;
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
