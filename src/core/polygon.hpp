// Areas on the ground (clip, the viewer's area tool): polygons with holes and multipolygons in the
// dataset CRS's units (plain planar geometry, no PROJ), with a point-in-polygon test that is exact on
// edges (a point on an edge or vertex is inside) and goes through an index of the edges by slabs of y
// (a segment tree whose edge lists are sorted left to right), and their strict parsing from WKT
// (POLYGON / MULTIPOLYGON) and GeoJSON (a Polygon or MultiPolygon geometry, Feature or
// FeatureCollection of them).
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <utility>
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
// The test goes through an index built once by the constructor. The y-range is cut into slabs
// (leaves) of 2 vertices each (4 or 8 past a million vertices); over them, a binary segment tree. An
// edge meeting at most 3 leaves is listed in each (tested directly there); a longer one in the leaves
// holding its ends and in the O(log leaves) tree nodes covering exactly the leaves it crosses
// entirely. In a node, each polygon's edges span the node's whole height; where they do not cross
// (any valid polygon; checked at the node's bottom and top) they are sorted left to right once, so a
// point counts those right of it by a binary search and tests only the few within rounding distance
// of it. A point examines its leaf's edges and searches the nodes above its leaf: O(log^2 vertices)
// edges for any polygon (a star of 100k thin spikes: about 100; an outline: about 4), where a band
// of y examines every edge a horizontal line crosses (tens of thousands on such a star). The answer
// is, bit for bit, that of testing every edge: the same cross products, the search deciding only
// edges farther from the point than their rounding. Edges that cross in a node (self-intersecting or
// overlapping rings of one polygon) are tested one by one there: correct, not fast.
// Memory: 16 bytes a vertex for the vertices, about 24 more for the index of an outline (10 past a
// million vertices); the tree holds at most 12 entries per edge (stars, spirals: about 60 bytes a
// vertex), the leaves made taller where it would hold more.
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
    // entries (edge references) the index holds over its leaves and tree nodes.
    std::size_t edges_examined(double x, double y) const;
    std::size_t index_entries() const { return leaf_edges_.size() + node_edges_.size(); }
    // The entries in sorted groups of the tree (searched); the others are in leaves, in groups of
    // fewer than 4 edges, or in groups whose edges cross (tested one by one).
    std::size_t searched_entries() const;
    // Bytes the polygon holds: its vertices and its index.
    std::size_t held_bytes() const;

private:
    // A polygon's edges in one tree node, node_edges_[begin .. the next group's begin): sorted left to
    // right and searched, or tested one by one.
    struct Group {
        std::uint32_t begin = 0;
        std::uint32_t polygon = 0;
        bool sorted = false;
    };
    struct Box {
        double x0, y0, x1, y1;
    };
    class OddPolygons;

    void build_index();
    void index_leaves(std::span<const double> bottoms);
    std::size_t bucket_of(double y) const;
    void build_groups(std::span<const std::uint32_t> node_starts, double scale);
    bool sort_group(std::span<std::uint32_t> edges, double bottom, double top,
                    std::vector<std::pair<double, std::uint32_t>>& keys) const;
    template <bool kCount>
    bool test(double x, double y, std::size_t& examined) const;
    template <bool kCount>
    bool test_each(std::span<const std::uint32_t> edges, double x, double y, OddPolygons& odd,
                   std::size_t& examined) const;
    template <bool kCount>
    bool search(std::span<const std::uint32_t> edges, std::uint32_t polygon, double x, double y, OddPolygons& odd,
                std::size_t& examined) const;
    template <bool kCount>
    std::size_t first_not_left(std::span<const std::uint32_t> edges, double x, double y,
                               std::size_t& examined) const;
    bool any_meets(std::span<const std::uint32_t> edges, const Box& box) const;
    bool group_touches_box(std::size_t node, std::size_t group, const Box& box) const;
    bool in_box(double x, double y) const { return x >= min_x_ && x <= max_x_ && y >= min_y_ && y <= max_y_; }
    std::uint32_t polygon_of(std::uint32_t edge) const;
    std::size_t leaf_of(double y) const;
    std::span<const std::uint32_t> leaf(std::size_t k) const;
    std::span<const std::uint32_t> group(std::size_t g) const;
    std::pair<double, double> node_heights(std::size_t node) const;

    // Every ring's vertices, each ring followed by its first vertex again: an edge is named by its
    // first vertex i and ends at i + 1.
    std::vector<XY> vertices_;
    std::vector<std::uint32_t> ring_starts_;     // where each ring starts in vertices_, then the end
    std::vector<std::uint32_t> polygon_starts_;  // where each polygon (its outer ring) starts, then the end
    // Leaf k holds the y values [leaf_records_[k].bottom, leaf_records_[k + 1].bottom) and lists the edges
    // leaf_edges_[leaf_records_[k].first .. leaf_records_[k + 1].first) in ascending order; a last record
    // (bottom +infinity) ends the last leaf. A y value's leaf is found through uniform buckets of y
    // (bucket_of), bucket b naming its leaves [bucket_leaves_[b], bucket_leaves_[b + 1]).
    struct Leaf {
        double bottom = 0;
        std::uint32_t first = 0;  // its first edge in leaf_edges_
        std::uint32_t path = 0;   // bit d: whether the ancestor d levels up, node (leaves_ + k) >> d, has edges
    };
    std::vector<Leaf> leaf_records_;
    std::vector<std::uint32_t> leaf_edges_, bucket_leaves_;
    double bucket_scale_ = 0;
    // The tree over leaves_ leaves (a power of two; those past the last leaf record are empty): node
    // 1 is the root, node n's children 2n and 2n + 1, leaf k's node leaves_ + k. Node n's groups are
    // groups_[node_groups_[n] .. node_groups_[n + 1]), followed by one group marking the end.
    std::size_t leaves_ = 0;
    std::vector<std::uint32_t> node_groups_, node_edges_;
    std::vector<Group> groups_;
    // What the search leaves to direct tests: edges within margin_ of the point in x (far more than
    // the rounding of the cross products and of the sorting); 0 when the coordinates are too large or
    // too small to bound that rounding (every group then tested one by one).
    double margin_ = 0;
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
