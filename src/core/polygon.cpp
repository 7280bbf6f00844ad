// MultiPolygon: the union of even-odd polygons with points on edges inside, tested through a segment
// tree of the edges over slabs of y whose lists are sorted left to right; and the WKT and GeoJSON parsers.
#include "core/polygon.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <bit>
#include <cctype>
#include <cmath>
#include <limits>
#include <numeric>
#include <fstream>

#include "core/error.hpp"
#include "core/json_reader.hpp"
#include "core/text.hpp"
#include "core/regular_file.hpp"

namespace lidarscout {
namespace {

Error polygon_error(const std::string& cause) { return Error::in_stage("polygon", cause); }

// Drops a repeated closing vertex and checks the ring.
Ring closed_ring(Ring ring) {
    if (ring.size() > 1 && ring.front() == ring.back()) ring.pop_back();
    for (const XY& v : ring) {
        if (!std::isfinite(v.x) || !std::isfinite(v.y)) throw polygon_error("a vertex is not a finite number");
    }
    if (ring.size() < 3) throw polygon_error("a ring needs at least 3 distinct vertices, it has " +
                                             std::to_string(ring.size()));
    return ring;
}

// (b - a) x ((x, y) - a): zero when (x, y) lies on the line through a and b, > 0 when left of a -> b.
double cross(const XY& a, const XY& b, double x, double y) { return (b.x - a.x) * (y - a.y) - (b.y - a.y) * (x - a.x); }

// Whether (x, y), on the line through a and b (their cross product is zero), lies on the segment a-b.
bool within(const XY& a, const XY& b, double x, double y) {
    return x >= std::min(a.x, b.x) && x <= std::max(a.x, b.x) && y >= std::min(a.y, b.y) && y <= std::max(a.y, b.y);
}

// Whether a ray from (x, y) towards +x crosses a-b, given their cross product: a-b straddles y (half-open,
// so that a vertex on the ray counts once) and (x, y) lies left of it when it goes up, right when down.
// Branch-free: in a crowded list these outcomes are unpredictable.
bool crossed(const XY& a, const XY& b, double y, double cross) {
    const bool b_above = b.y > y;
    return ((a.y > y) != b_above) & ((cross > 0) == b_above);
}

// Whether segment a-b meets the box (Liang-Barsky clipping of the segment to the box).
bool segment_meets_box(const XY& a, const XY& b, double x0, double y0, double x1, double y1) {
    double t0 = 0, t1 = 1;
    const double d[2] = {b.x - a.x, b.y - a.y}, lo[2] = {x0 - a.x, y0 - a.y}, hi[2] = {x1 - a.x, y1 - a.y};
    for (int k = 0; k < 2; ++k) {
        if (d[k] == 0) {
            if (lo[k] > 0 || hi[k] < 0) return false;
            continue;
        }
        double enter = lo[k] / d[k], leave = hi[k] / d[k];
        if (enter > leave) std::swap(enter, leave);
        t0 = std::max(t0, enter), t1 = std::min(t1, leave);
        if (t0 > t1) return false;
    }
    return true;
}

// The shoelace area of a ring given with its closing vertex repeated.
double ring_area(std::span<const XY> closed) {
    double twice = 0;
    for (std::size_t i = 0; i + 1 < closed.size(); ++i) {
        twice += closed[i].x * closed[i + 1].y - closed[i + 1].x * closed[i].y;
    }
    return std::abs(twice) / 2;
}

// The index names vertices, and counts its entries, in 32 bits: at most 2 + kNodeEntriesPerEdge per edge.
constexpr std::size_t kMaxVertices = std::numeric_limits<std::uint32_t>::max() / 16;

// Leaves hold 2 vertices (a point tests about 4 edges of an outline directly), or 4 or 8 past a million
// vertices (about 26 bytes a vertex for the vertices and index, rather than 44); more when the tree's
// entries would pass their cap: an edge is in about log2 of the leaves it spans nodes, over the
// polygon at most kNodeEntriesPerEdge per edge, else the leaves are made twice as tall (a spiral, a
// star of millions of spikes).
constexpr std::size_t kNodeEntriesPerEdge = 12, kShortEdgeLeaves = 3;
std::size_t vertices_per_leaf(std::size_t vertices) {
    return std::clamp<std::size_t>(std::bit_ceil((vertices >> 19) + 1), 2, 8);
}
// Groups of fewer edges are tested one by one (a search would examine about as many).
constexpr std::size_t kSmallestSortedGroup = 4;

// Rounding, in units of u S (u = 2^-53, S the largest coordinate magnitude; each bound generous):
// x_at errs by at most 16 u S, so a group sorted by it is accepted when each edge lies at most
// kOrderSlack left of the ones before it at the node's bottom and top, and then at every height
// between (it is linear) no edge lies more than kOrderSlack + 32 u S left of an earlier one. A cross
// product errs by at most about 4u (|dx| |y - a.y| + |dy| |x - a.x|), with |y - a.y| <= |dy| for an
// edge spanning y: its sign is right for points farther than 32 u S from the edge in x. So edges that
// a search at x -+ kMargin puts left or right of the point are so, by the signs the direct test
// would compute (kMargin > 2 * 32 + 160 + the rounding of x -+ kMargin).
constexpr double kRoundingUnit = std::numeric_limits<double>::epsilon() / 2, kOrderSlack = 128, kMargin = 512;
// Where those bounds hold: products of coordinates stay normal numbers (no overflow, underflow far
// below the margin) and a node is at least kMinHeight S tall. Elsewhere groups are tested one by one.
constexpr double kMinScale = 1e-100, kMaxScale = 1e100, kMinHeight = 1e-100;

// Calls fn with each edge's first vertex: ring r's edges start at ring_starts[r] .. ring_starts[r + 1] - 2.
template <typename Fn>
void for_each_edge(std::span<const std::uint32_t> ring_starts, Fn&& fn) {
    for (std::size_t r = 0; r + 1 < ring_starts.size(); ++r) {
        for (std::uint32_t i = ring_starts[r]; i + 1 < ring_starts[r + 1]; ++i) fn(i);
    }
}

// The x of edge a-b at height y (within its y-range; the edge not horizontal).
double x_at(const XY& a, const XY& b, double y) { return a.x + (b.x - a.x) * ((y - a.y) / (b.y - a.y)); }

// Whether edge a-b, which spans y, passes right of (x, y) by its cross product's sign (zero: false).
bool passes_right(const XY& a, const XY& b, double x, double y) {
    const double c = cross(a, b, x, y);
    return b.y > a.y ? c > 0 : c < 0;
}

// Cuts sorted ys into leaves of about per_leaf values (equal ones in one leaf): their bottoms.
std::vector<double> leaf_bottoms(std::span<const double> ys, std::size_t per_leaf) {
    std::vector<double> out;
    for (std::size_t j = 0; j < ys.size();) {
        out.push_back(ys[j]);
        j += per_leaf;
        if (j < ys.size() && ys[j] == out.back()) j = std::upper_bound(ys.begin() + j, ys.end(), ys[j]) - ys.begin();
    }
    return out;
}

// Calls fn with the nodes of a tree over `leaves` leaves (a power of two) that cover [first, end) exactly.
template <typename Fn>
void for_each_cover_node(std::size_t first, std::size_t end, std::size_t leaves, Fn&& fn) {
    for (first += leaves, end += leaves; first < end; first >>= 1, end >>= 1) {
        if (first & 1) fn(first++);
        if (end & 1) fn(--end);
    }
}

// Where an edge goes, from the leaves holding its lower end (low; whether the end lies on that leaf's
// bottom) and its upper end (high): leaf(k) for the leaves where it is tested directly, node(n) for the
// nodes covering the leaves it spans entirely. A short edge (most of an outline's) is in the leaves it
// meets, so that a point's work stays in its leaf; a longer one in the leaves holding its ends and the
// nodes over those between.
template <typename Leaf, typename Node>
void place_edge(bool on_bottom, std::size_t leaves, std::size_t low, std::size_t high, Leaf&& leaf, Node&& node) {
    if (high - low < kShortEdgeLeaves) {
        for (std::size_t k = low; k <= high; ++k) leaf(k);
        return;
    }
    const std::size_t first = on_bottom ? low : low + 1;  // spanned: [first, high)
    if (low < first && low < high) leaf(low);
    leaf(high);
    if (first < high) for_each_cover_node(first, high, leaves, node);
}

// Lists edges by key: lists(i, add) calls add(k) for each list k that edge i belongs in. starts gets
// count + 1 offsets into items; each list in ascending edge order.
template <typename Lists>
void bucket_edges(std::span<const std::uint32_t> ring_starts, std::size_t count, Lists&& lists,
                  std::vector<std::uint32_t>& starts, std::vector<std::uint32_t>& items) {
    starts.assign(count + 1, 0);
    for_each_edge(ring_starts, [&](std::uint32_t i) { lists(i, [&](std::size_t k) { ++starts[k + 1]; }); });
    std::partial_sum(starts.begin(), starts.end(), starts.begin());
    items.resize(starts.back());
    for_each_edge(ring_starts, [&](std::uint32_t i) { lists(i, [&](std::size_t k) { items[starts[k]++] = i; }); });
    std::copy_backward(starts.begin(), starts.end() - 1, starts.end());  // each list's end back to its start
    starts[0] = 0;
}

}  // namespace

// The polygons whose edges right of a point were crossed an odd number of times: each list of edges
// adds its polygon when it counted an odd number; a polygon is odd when added an odd number of times.
class MultiPolygon::OddPolygons {
public:
    explicit OddPolygons(bool one_polygon) : one_(one_polygon) {}

    void add(std::uint32_t polygon, bool odd) {
        if (one_) {
            parity_ = parity_ != odd;
        } else if (odd) {
            add_odd(polygon);
        }
    }
    bool any() {
        if (one_) return parity_;
        const auto first = std::span(inline_).first(std::min(count_, kInline));
        if (more_.empty() && std::all_of(first.begin(), first.end(), [&](std::uint32_t p) { return p == first[0]; })) {
            return count_ % 2 == 1;  // all the same polygon, or none
        }
        more_.insert(more_.end(), first.begin(), first.end());
        std::sort(more_.begin(), more_.end());
        for (auto at = more_.begin(); at != more_.end();) {
            const auto end = std::upper_bound(at, more_.end(), *at);
            if ((end - at) % 2 == 1) return true;
            at = end;
        }
        return false;
    }

private:
    void add_odd(std::uint32_t polygon) {
        if (count_ < kInline) inline_[count_] = polygon;
        else more_.push_back(polygon);
        ++count_;
    }

    static constexpr std::size_t kInline = 32;
    std::array<std::uint32_t, kInline> inline_;
    std::vector<std::uint32_t> more_;
    std::size_t count_ = 0;
    bool one_, parity_ = false;  // one polygon: its parity only
};

MultiPolygon::MultiPolygon(std::vector<std::vector<Ring>> polygons) {
    if (polygons.empty()) throw polygon_error("the polygon has no rings");
    std::size_t total = 0;  // vertices_'s size: every ring with its closing vertex
    for (auto& rings : polygons) {
        if (rings.empty()) throw polygon_error("a polygon has no outer ring");
        for (auto& ring : rings) ring = closed_ring(std::move(ring)), total += ring.size() + 1;
    }
    if (total > kMaxVertices) throw polygon_error("the polygon has more than " + std::to_string(kMaxVertices) +
                                                  " vertices");
    vertices_.reserve(total);
    min_x_ = min_y_ = INFINITY;
    max_x_ = max_y_ = -INFINITY;
    for (auto& rings : polygons) {
        polygon_starts_.push_back(static_cast<std::uint32_t>(vertices_.size()));
        for (auto& ring : rings) {
            ring_starts_.push_back(static_cast<std::uint32_t>(vertices_.size()));
            for (const XY& v : ring) {
                min_x_ = std::min(min_x_, v.x), max_x_ = std::max(max_x_, v.x);
                min_y_ = std::min(min_y_, v.y), max_y_ = std::max(max_y_, v.y);
            }
            vertices_.insert(vertices_.end(), ring.begin(), ring.end());
            vertices_.push_back(ring.front());
            Ring().swap(ring);  // copied: the input's memory goes as it is read
        }
    }
    ring_starts_.push_back(static_cast<std::uint32_t>(vertices_.size()));
    polygon_starts_.push_back(static_cast<std::uint32_t>(vertices_.size()));
    build_index();
}

// The leaves (sorted vertex ys cut every 8 values, or more where the tree would hold too many
// entries), each edge listed in its end leaves and its covering nodes, then each node's groups.
void MultiPolygon::build_index() {
    const double scale = std::max({std::abs(min_x_), std::abs(max_x_), std::abs(min_y_), std::abs(max_y_)});
    margin_ = scale >= kMinScale && scale <= kMaxScale ? kMargin * kRoundingUnit * scale : 0;
    std::vector<std::uint32_t> vertex_leaf(vertices_.size());
    const auto place = [&](std::uint32_t i, auto&& leaf, auto&& node) {
        const bool up = vertices_[i + 1].y >= vertices_[i].y;
        const std::uint32_t low = vertex_leaf[up ? i : i + 1], high = vertex_leaf[up ? i + 1 : i];
        const double lo = std::min(vertices_[i].y, vertices_[i + 1].y);
        place_edge(leaf_records_[low].bottom == lo, leaves_, low, high, leaf, node);
    };
    const auto none = [](std::size_t) {};
    {
        std::vector<double> ys(vertices_.size());
        std::transform(vertices_.begin(), vertices_.end(), ys.begin(), [](const XY& v) { return v.y; });
        std::sort(ys.begin(), ys.end());
        const std::size_t cap = kNodeEntriesPerEdge * vertex_count();
        for (std::size_t per_leaf = vertices_per_leaf(vertices_.size());; per_leaf *= 2) {
            index_leaves(leaf_bottoms(ys, per_leaf));
            for (std::size_t i = 0; i < vertices_.size(); ++i) vertex_leaf[i] = leaf_of(vertices_[i].y);
            std::size_t entries = 0;
            for_each_edge(ring_starts_, [&](std::uint32_t i) { place(i, none, [&](std::size_t) { ++entries; }); });
            if (entries <= cap) break;
        }
    }
    {
        std::vector<std::uint32_t> starts;
        bucket_edges(ring_starts_, leaf_records_.size() - 1, [&](std::uint32_t i, auto&& add) { place(i, add, none); },
                     starts, leaf_edges_);
        for (std::size_t k = 0; k < leaf_records_.size(); ++k) leaf_records_[k].first = starts[k];
    }
    std::vector<std::uint32_t> node_starts;
    bucket_edges(ring_starts_, 2 * leaves_, [&](std::uint32_t i, auto&& add) { place(i, none, add); }, node_starts,
                 node_edges_);
    vertex_leaf = {};
    build_groups(node_starts, scale);
    for (std::size_t k = 0; k + 1 < leaf_records_.size(); ++k) {
        for (std::size_t n = leaves_ + k, d = 0; n > 0; n >>= 1, ++d) {
            if (node_groups_[n] < node_groups_[n + 1]) leaf_records_[k].path |= std::uint32_t{1} << d;
        }
    }
}

// The leaves' records from their bottoms (and the last record); the tree's size, and the table of
// leaves by buckets of y.
void MultiPolygon::index_leaves(std::span<const double> bottoms) {
    leaf_records_.assign(bottoms.size() + 1, Leaf{});
    for (std::size_t k = 0; k < bottoms.size(); ++k) leaf_records_[k].bottom = bottoms[k];
    leaf_records_.back().bottom = INFINITY;
    leaves_ = std::bit_ceil(bottoms.size());
    bucket_scale_ = static_cast<double>(bottoms.size()) / (max_y_ - min_y_);
    if (!std::isfinite(bucket_scale_)) bucket_scale_ = 0;
    bucket_leaves_.assign(bottoms.size() + 1, 0);
    for (const double y : bottoms) ++bucket_leaves_[bucket_of(y) + 1];
    std::partial_sum(bucket_leaves_.begin(), bucket_leaves_.end(), bucket_leaves_.begin());
}

// floor((y - min_y_) * bucket_scale_), clamped: never decreasing as y grows, so the leaf holding y
// (the last whose bottom is at most y) is the last of bucket b's leaves at most y, or the one before them.
std::size_t MultiPolygon::bucket_of(double y) const {
    const double b = (y - min_y_) * bucket_scale_;  // floored by the conversion below, being positive
    if (!(b > 0)) return 0;  // also NaN
    const std::size_t last = bucket_leaves_.size() - 2;
    return b >= static_cast<double>(last) ? last : static_cast<std::size_t>(b);
}

// Splits each node's edges by polygon and sorts each group that is large enough, in a node tall enough.
void MultiPolygon::build_groups(std::span<const std::uint32_t> node_starts, double scale) {
    node_groups_.assign(2 * leaves_ + 1, 0);
    groups_.clear();
    std::vector<std::pair<double, std::uint32_t>> keys;
    for (std::size_t n = 0; n < 2 * leaves_; ++n) {
        node_groups_[n] = static_cast<std::uint32_t>(groups_.size());
        for (std::uint32_t begin = node_starts[n], end = begin; begin < node_starts[n + 1]; begin = end) {
            const std::uint32_t polygon = polygon_of(node_edges_[begin]), next = polygon_starts_[polygon + 1];
            while (end < node_starts[n + 1] && node_edges_[end] < next) ++end;
            const auto edges = std::span(node_edges_).subspan(begin, end - begin);
            const auto [bottom, top] = node_heights(n);
            const bool sorted = margin_ > 0 && edges.size() >= kSmallestSortedGroup &&
                                top - bottom >= kMinHeight * scale && sort_group(edges, bottom, top, keys);
            groups_.push_back({begin, polygon, sorted});
        }
    }
    node_groups_[2 * leaves_] = static_cast<std::uint32_t>(groups_.size());
    groups_.push_back({static_cast<std::uint32_t>(node_edges_.size()), 0, false});  // the end of the last
}

// Sorts edges spanning [bottom, top] by their x in the middle; false (edges left as they were) when
// their order at the bottom or the top disagrees beyond rounding (they cross).
bool MultiPolygon::sort_group(std::span<std::uint32_t> edges, double bottom, double top,
                              std::vector<std::pair<double, std::uint32_t>>& keys) const {
    const auto x_of = [&](std::uint32_t i, double y) { return x_at(vertices_[i], vertices_[i + 1], y); };
    keys.clear();
    for (const std::uint32_t i : edges) keys.emplace_back(x_of(i, bottom) + x_of(i, top), i);
    std::sort(keys.begin(), keys.end());
    const double slack = margin_ / kMargin * kOrderSlack;
    double right_bottom = -INFINITY, right_top = -INFINITY;  // the rightmost so far
    for (const auto& [key, i] : keys) {
        const double xb = x_of(i, bottom), xt = x_of(i, top);
        if (xb < right_bottom - slack || xt < right_top - slack) return false;
        right_bottom = std::max(right_bottom, xb), right_top = std::max(right_top, xt);
    }
    std::transform(keys.begin(), keys.end(), edges.begin(), [](const auto& k) { return k.second; });
    return true;
}

std::uint32_t MultiPolygon::polygon_of(std::uint32_t edge) const {
    if (polygon_starts_.size() == 2) return 0;
    return static_cast<std::uint32_t>(std::upper_bound(polygon_starts_.begin(), polygon_starts_.end(), edge) -
                                      polygon_starts_.begin() - 1);
}

std::size_t MultiPolygon::leaf_of(double y) const {
    const std::size_t b = bucket_of(y);
    std::size_t k = bucket_leaves_[b];
    const std::size_t end = bucket_leaves_[b + 1];
    if (end - k > 8) {  // a crowded bucket (vertices far from uniform in y)
        const auto after = std::upper_bound(leaf_records_.begin() + k, leaf_records_.begin() + end, y,
                                            [](double v, const Leaf& leaf) { return v < leaf.bottom; });
        return static_cast<std::size_t>(after - leaf_records_.begin()) - 1;
    }
    while (k < end && leaf_records_[k].bottom <= y) ++k;
    return k - 1;
}

std::span<const std::uint32_t> MultiPolygon::leaf(std::size_t k) const {
    return std::span(leaf_edges_).subspan(leaf_records_[k].first, leaf_records_[k + 1].first - leaf_records_[k].first);
}

std::span<const std::uint32_t> MultiPolygon::group(std::size_t g) const {
    return std::span(node_edges_).subspan(groups_[g].begin, groups_[g + 1].begin - groups_[g].begin);
}

// The heights node n covers: its first leaf's bottom, and the next leaf's (infinite past the last).
std::pair<double, double> MultiPolygon::node_heights(std::size_t n) const {
    const int depth = std::bit_width(n) - 1;
    const std::size_t width = leaves_ >> depth, first = (n - (std::size_t{1} << depth)) * width;
    const auto bottom = [&](std::size_t k) { return k < leaf_records_.size() ? leaf_records_[k].bottom : INFINITY; };
    return {bottom(first), bottom(first + width)};
}

// The point's leaf's edges one by one, then each node above the leaf that has edges: its groups
// searched or tested.
template <bool kCount>
bool MultiPolygon::test(double x, double y, std::size_t& examined) const {
    if (leaf_records_.empty() || !in_box(x, y)) return false;
    const std::size_t k = leaf_of(y);
    OddPolygons odd(polygon_starts_.size() == 2);
    if (test_each<kCount>(leaf(k), x, y, odd, examined)) return true;
    for (std::uint32_t path = leaf_records_[k].path; path != 0; path &= path - 1) {
        const std::size_t n = (leaves_ + k) >> std::countr_zero(path);
        for (std::size_t g = node_groups_[n]; g < node_groups_[n + 1]; ++g) {
            const auto edges = group(g);
            if (groups_[g].sorted ? search<kCount>(edges, groups_[g].polygon, x, y, odd, examined)
                                  : test_each<kCount>(edges, x, y, odd, examined)) {
                return true;
            }
        }
    }
    return odd.any();
}

// The direct test of each edge (ascending, so grouped by polygon): true when (x, y) lies on one.
template <bool kCount>
bool MultiPolygon::test_each(std::span<const std::uint32_t> edges, double x, double y, OddPolygons& odd,
                             std::size_t& examined) const {
    const XY* vertices = vertices_.data();
    std::uint32_t polygon = 0, polygon_end = 0;
    bool inside = false;  // in the polygon whose edges are being read
    for (const std::uint32_t i : edges) {
        if (i >= polygon_end) {  // the first edge of a later polygon: the previous one is counted
            odd.add(polygon, inside), inside = false;
            polygon = polygon_of(i), polygon_end = polygon_starts_[polygon + 1];
        }
        if constexpr (kCount) ++examined;
        const XY &a = vertices[i], &b = vertices[i + 1];
        const double c = cross(a, b, x, y);
        if (c == 0 && within(a, b, x, y)) return true;  // on the edge
        inside = inside != crossed(a, b, y, c);
    }
    odd.add(polygon, inside);
    return false;
}

// A sorted group spanning y: the edges left of x - margin_ skipped by a binary search, those after it
// tested directly until one passes right of x + margin_, which with all after it the ray crosses.
template <bool kCount>
bool MultiPolygon::search(std::span<const std::uint32_t> edges, std::uint32_t polygon, double x, double y,
                          OddPolygons& odd, std::size_t& examined) const {
    bool inside = false;
    for (std::size_t k = first_not_left<kCount>(edges, x - margin_, y, examined); k < edges.size(); ++k) {
        const XY &a = vertices_[edges[k]], &b = vertices_[edges[k] + 1];
        if constexpr (kCount) examined += 2;
        if (passes_right(a, b, x + margin_, y)) {
            inside = inside != ((edges.size() - k) % 2 == 1);
            break;
        }
        const double c = cross(a, b, x, y);
        if (c == 0 && within(a, b, x, y)) return true;
        inside = inside != crossed(a, b, y, c);
    }
    odd.add(polygon, inside);
    return false;
}

// In a sorted group spanning y, the first edge that passes right of (x, y): a binary search.
template <bool kCount>
std::size_t MultiPolygon::first_not_left(std::span<const std::uint32_t> edges, double x, double y,
                                         std::size_t& examined) const {
    std::size_t first = 0;
    for (std::size_t count = edges.size(); count > 0;) {
        const std::size_t step = count / 2, middle = first + step;
        if constexpr (kCount) ++examined;
        if (passes_right(vertices_[edges[middle]], vertices_[edges[middle] + 1], x, y)) {
            count = step;
        } else {
            first = middle + 1, count -= step + 1;
        }
    }
    return first;
}

bool MultiPolygon::contains(double x, double y) const {
    std::size_t unused = 0;
    return test<false>(x, y, unused);
}

std::size_t MultiPolygon::edges_examined(double x, double y) const {
    std::size_t examined = 0;
    test<true>(x, y, examined);
    return examined;
}

// A corner inside, or an edge meeting the box: those of the leaves over the box's heights, and of
// the nodes above them (in a sorted group, only the edges not certainly left or right of the box).
bool MultiPolygon::touches_box(double x0, double y0, double x1, double y1) const {
    if (leaf_records_.empty() || x0 > max_x_ || x1 < min_x_ || y0 > max_y_ || y1 < min_y_) return false;
    if (contains(x0, y0)) return true;  // the box inside the polygon (or a corner on it)
    const Box box{x0, y0, x1, y1};
    const std::size_t first = leaf_of(std::max(y0, min_y_)), last = leaf_of(std::min(y1, max_y_));
    for (std::size_t k = first; k <= last; ++k) {
        if (any_meets(leaf(k), box)) return true;
    }
    for (std::size_t from = leaves_ + first, to = leaves_ + last; from > 0; from >>= 1, to >>= 1) {
        for (std::size_t n = from; n <= to; ++n) {
            for (std::size_t g = node_groups_[n]; g < node_groups_[n + 1]; ++g) {
                if (group_touches_box(n, g, box)) return true;
            }
        }
    }
    return false;
}

bool MultiPolygon::any_meets(std::span<const std::uint32_t> edges, const Box& b) const {
    return std::any_of(edges.begin(), edges.end(), [&](std::uint32_t i) {
        return segment_meets_box(vertices_[i], vertices_[i + 1], b.x0, b.y0, b.x1, b.y1);
    });
}

// Whether an edge of group g (in node n) meets the box; in a sorted group, those before the first
// not left of the box at its clamped bottom or top are left of it at every height between, and those
// from the last first-right-of-it on are right of it: only the edges between are tried.
bool MultiPolygon::group_touches_box(std::size_t n, std::size_t g, const Box& box) const {
    auto edges = group(g);
    if (groups_[g].sorted) {
        const auto [bottom, top] = node_heights(n);
        const double lo = std::max(bottom, box.y0), hi = std::min(top, box.y1);
        const double left = std::max(box.x0, min_x_) - margin_, right = std::min(box.x1, max_x_) + margin_;
        std::size_t unused = 0;
        const std::size_t begin = std::min(first_not_left<false>(edges, left, lo, unused),
                                           first_not_left<false>(edges, left, hi, unused));
        const std::size_t end = std::max(first_not_left<false>(edges, right, lo, unused),
                                         first_not_left<false>(edges, right, hi, unused));
        edges = edges.subspan(begin, std::max(end, begin) - begin);
    }
    return any_meets(edges, box);
}

double MultiPolygon::area() const {
    double sum = 0;
    for (std::size_t p = 0, r = 0; p + 1 < polygon_starts_.size(); ++p) {
        double polygon = 0;  // the outer ring's area, less its holes' (none below zero)
        for (bool outer = true; r + 1 < ring_starts_.size() && ring_starts_[r] < polygon_starts_[p + 1]; ++r) {
            const std::size_t first = ring_starts_[r], size = ring_starts_[r + 1] - first;
            polygon += (outer ? 1 : -1) * ring_area(std::span(vertices_).subspan(first, size));
            outer = false;
        }
        sum += std::max(polygon, 0.0);
    }
    return sum;
}

std::size_t MultiPolygon::searched_entries() const {
    std::size_t entries = 0;
    for (std::size_t g = 0; g + 1 < groups_.size(); ++g) entries += groups_[g].sorted ? group(g).size() : 0;
    return entries;
}

std::size_t MultiPolygon::held_bytes() const {
    const std::size_t numbers = ring_starts_.capacity() + polygon_starts_.capacity() + leaf_edges_.capacity() +
                                bucket_leaves_.capacity() + node_groups_.capacity() + node_edges_.capacity();
    return vertices_.capacity() * sizeof(XY) + numbers * sizeof(std::uint32_t) +
           leaf_records_.capacity() * sizeof(Leaf) + groups_.capacity() * sizeof(Group);
}

std::size_t MultiPolygon::vertex_count() const {
    return ring_starts_.empty() ? 0 : vertices_.size() - (ring_starts_.size() - 1);
}

// ---- WKT

namespace {

class WktReader {
public:
    explicit WktReader(std::string_view text) : text_(text) {}

    MultiPolygon read() {
        const std::string word = keyword();
        std::vector<std::vector<Ring>> polygons;
        if (word == "POLYGON") {
            skip_dimension();
            polygons.push_back(polygon());
        } else if (word == "MULTIPOLYGON") {
            skip_dimension();
            expect('(');
            do polygons.push_back(polygon());
            while (take(','));
            expect(')');
        } else {
            fail("POLYGON or MULTIPOLYGON");
        }
        space();
        if (pos_ != text_.size()) fail("the end of the text");
        return MultiPolygon(std::move(polygons));
    }

private:
    std::vector<Ring> polygon() {
        std::vector<Ring> rings;
        expect('(');
        do rings.push_back(ring());
        while (take(','));
        expect(')');
        return rings;
    }

    Ring ring() {
        Ring r;
        expect('(');
        do r.push_back(vertex());
        while (take(','));
        expect(')');
        return r;
    }

    XY vertex() {
        XY v{number(), number()};
        if (dimensions_ > 2) number();
        if (dimensions_ > 3) number();
        return v;
    }

    double number() {
        space();
        const std::size_t start = pos_;
        while (pos_ < text_.size() && (std::isdigit(static_cast<unsigned char>(text_[pos_])) ||
                                       std::string_view("+-.eE").find(text_[pos_]) != std::string_view::npos)) {
            ++pos_;
        }
        const std::string s(text_.substr(start, pos_ - start));
        std::size_t used = 0;
        double v = 0;
        try {
            v = std::stod(s, &used);
        } catch (const std::exception&) {
            used = 0;
        }
        if (s.empty() || used != s.size()) pos_ = start, fail("a number");
        return v;
    }

    std::string keyword() {
        space();
        std::string w;
        while (pos_ < text_.size() && std::isalpha(static_cast<unsigned char>(text_[pos_]))) {
            w += static_cast<char>(std::toupper(static_cast<unsigned char>(text_[pos_++])));
        }
        return w;
    }

    // "Z", "M" or "ZM" after the type: more ordinates per vertex, ignored.
    void skip_dimension() {
        const std::size_t at = pos_;
        const std::string w = keyword();
        if (w == "Z" || w == "M") dimensions_ = 3;
        else if (w == "ZM") dimensions_ = 4;
        else if (!w.empty()) pos_ = at, fail("'(' or Z, M, ZM");
    }

    void space() {
        while (pos_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[pos_]))) ++pos_;
    }
    bool take(char c) {
        space();
        if (pos_ < text_.size() && text_[pos_] == c) return ++pos_, true;
        return false;
    }
    void expect(char c) {
        if (!take(c)) fail(std::string("'") + c + "'");
    }
    [[noreturn]] void fail(const std::string& expected) const {
        const std::string found = pos_ < text_.size() ? "'" + std::string(text_.substr(pos_, 12)) + "'" : "the end";
        throw polygon_error("WKT: expected " + expected + " at character " + std::to_string(pos_ + 1) + ", found " +
                            found);
    }

    std::string_view text_;
    std::size_t pos_ = 0;
    int dimensions_ = 2;
};

// ---- GeoJSON

// The most vertices a GeoJSON polygon may have (its rings then take ~80-160 MB).
constexpr std::uint64_t kMaxGeoJsonVertices = 5'000'000;

// The reader's limits for a GeoJSON document: room for the vertices, written at length.
JsonLimits geojson_limits() {
    JsonLimits limits;
    limits.max_bytes = 512ull << 20;
    return limits;
}

Error position_error() { return polygon_error("GeoJSON: a position is not an array of at least two numbers"); }

// GeoJSON "coordinates" values, read as they stream by (diverted from the document: JsonStreaming)
// into rings, 16 bytes a vertex. Each value is a tree of arrays whose leaves are rings (arrays of
// positions); what it must be (a Polygon's rings, a MultiPolygon's polygons) is known from its
// geometry's type, read later. A value of another shape (a member named "coordinates" may be
// anywhere, in a Feature's properties too) is only refused where a geometry uses it.
class Coordinates final : public JsonValueEvents {
public:
    struct Nest {
        // kOther: not an array; kBadPosition: holds a position that is not two numbers or more
        enum Kind { kEmpty, kPositions, kArrays, kOther, kBadPosition } kind = kOther;
        Ring ring;                // kPositions: its positions
        std::vector<Nest> items;  // kArrays: its arrays
    };

    // The value of ordinal `i` (taken: each is used once).
    Nest take(const nlohmann::json& ordinal) {
        if (!ordinal.is_number_unsigned() || ordinal.get<std::size_t>() >= values_.size()) return {};
        return std::move(values_[ordinal.get<std::size_t>()]);
    }

    void scalar(const nlohmann::json& v) override {
        if (stack_.empty()) return values_.push_back({});
        Frame& f = stack_.back();
        if (!v.is_number() || (f.kind != Frame::kEmpty && f.kind != Frame::kPosition)) return bad();
        f.kind = Frame::kPosition;
        if (f.numbers < 2) f.xy[f.numbers] = v.get<double>();
        ++f.numbers;
    }
    void open(bool object) override {
        if (object || (!stack_.empty() && stack_.back().kind == Frame::kPosition)) bad();
        stack_.emplace_back();
    }
    void key(const std::string&) override {}
    void close() override {
        Frame f = std::move(stack_.back());
        stack_.pop_back();
        if (f.kind == Frame::kPosition && f.numbers < 2) bad();
        if (stack_.empty()) {
            values_.push_back(bad_ ? Nest{Nest::kBadPosition, {}, {}} : f.nest());
            bad_ = false;
            return;
        }
        if (bad_) return;  // (the rest of the value is not kept)
        Frame& parent = stack_.back();
        if (f.kind == Frame::kPosition) {
            if (parent.kind != Frame::kEmpty && parent.kind != Frame::kPositions) return bad();
            if (++vertices_ > kMaxGeoJsonVertices) {
                throw polygon_error("GeoJSON: more than the limit of " + std::to_string(kMaxGeoJsonVertices) +
                                    " vertices");
            }
            parent.kind = Frame::kPositions;
            parent.ring.push_back({f.xy[0], f.xy[1]});
            return;
        }
        if (parent.kind == Frame::kPositions) return bad();
        parent.kind = Frame::kArrays;
        parent.items.push_back(f.nest());
    }

private:
    struct Frame {  // an array being read
        enum Kind { kEmpty, kPosition, kPositions, kArrays } kind = kEmpty;
        double xy[2] = {0, 0};
        std::size_t numbers = 0;
        Ring ring;
        std::vector<Nest> items;

        Nest nest() {
            switch (kind) {
                case kEmpty: return {Nest::kEmpty, {}, {}};
                case kPositions: return {Nest::kPositions, std::move(ring), {}};
                case kArrays: return {Nest::kArrays, {}, std::move(items)};
                default: return {Nest::kBadPosition, {}, {}};  // (a bare position)
            }
        }
    };

    // The value being read is not arrays of positions: what it holds is dropped.
    void bad() {
        bad_ = true;
        for (Frame& f : stack_) f.ring = {}, f.items = {};
    }

    std::vector<Nest> values_;
    std::vector<Frame> stack_;
    bool bad_ = false;
    std::uint64_t vertices_ = 0;
};

std::vector<Ring> polygon_of(Coordinates::Nest&& c) {
    if (c.kind == Coordinates::Nest::kBadPosition) throw position_error();
    if (c.kind != Coordinates::Nest::kArrays) {
        throw polygon_error("GeoJSON: a Polygon's coordinates are not an array of rings");
    }
    std::vector<Ring> rings;
    for (auto& r : c.items) {
        if (r.kind == Coordinates::Nest::kBadPosition) throw position_error();
        if (r.kind != Coordinates::Nest::kPositions && r.kind != Coordinates::Nest::kEmpty) {
            throw polygon_error("GeoJSON: a ring is not an array of positions");
        }
        rings.push_back(std::move(r.ring));
    }
    return rings;
}

// The "type" of a GeoJSON object ("" when it has none; a type that is not a string is refused).
std::string geojson_type(const nlohmann::json& j) {
    try {
        return json_optional_string(j, "type").value_or("");
    } catch (const Error& e) {
        throw polygon_error("GeoJSON: " + e.cause());
    }
}

// (Nesting is bounded by the reader's depth limit, so the recursion is too.)
void add_geometry(const nlohmann::json& j, Coordinates& coordinates, std::vector<std::vector<Ring>>& out) {
    const std::string type = geojson_type(j);
    if (type == "Feature") {
        const nlohmann::json* geometry = json_field(j, "geometry");
        if (!geometry) throw polygon_error("GeoJSON: a Feature without a geometry");
        return add_geometry(*geometry, coordinates, out);
    }
    if (type == "FeatureCollection") {
        const nlohmann::json* features = json_field(j, "features");
        if (!features || !features->is_array()) {
            throw polygon_error("GeoJSON: a FeatureCollection without a features array");
        }
        for (const auto& f : *features) add_geometry(f, coordinates, out);
        return;
    }
    if (type != "Polygon" && type != "MultiPolygon") {
        throw polygon_error("GeoJSON: expected a Polygon or MultiPolygon geometry, found " +
                            (type.empty() ? std::string("no type") : "'" + display_excerpt(type) + "'"));
    }
    const nlohmann::json* ordinal = json_field(j, "coordinates");
    Coordinates::Nest c = ordinal ? coordinates.take(*ordinal) : Coordinates::Nest{};
    if (type == "Polygon") return out.push_back(polygon_of(std::move(c)));
    if (c.kind == Coordinates::Nest::kBadPosition) throw position_error();
    if (c.kind != Coordinates::Nest::kArrays && c.kind != Coordinates::Nest::kEmpty) {
        throw polygon_error("GeoJSON: a MultiPolygon's coordinates are not an array");
    }
    for (auto& p : c.items) out.push_back(polygon_of(std::move(p)));
}

// The polygon of the GeoJSON document read from `source`; a reader's error is the polygon stage's.
MultiPolygon read_geojson_polygon(const JsonSource& source) {
    Coordinates coordinates;
    const JsonStreaming diversion{{}, {}, {"coordinates"}, &coordinates};
    nlohmann::json j;
    try {
        j = read_json(source, "", geojson_limits(), &diversion);
    } catch (const Error& e) {
        const bool ours = e.cause().starts_with("polygon: ");  // (the vertex limit)
        throw Error(e.file(), e.offset(), (ours ? "" : "polygon: GeoJSON: ") + e.cause());
    }
    std::vector<std::vector<Ring>> polygons;
    add_geometry(j, coordinates, polygons);
    return MultiPolygon(std::move(polygons));
}

}  // namespace

MultiPolygon parse_wkt_polygon(std::string_view text) { return WktReader(text).read(); }

MultiPolygon parse_geojson_polygon(std::string_view text) {
    return read_geojson_polygon(text_json_source(text));
}

MultiPolygon read_polygon_argument(const std::string& argument) {
    std::string head;
    for (const char c : argument.substr(0, 20)) head += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    head.erase(0, head.find_first_not_of(" \t\n"));
    if (head.starts_with("POLYGON") || head.starts_with("MULTIPOLYGON")) return parse_wkt_polygon(argument);
    require_regular_file(argument);  // a FIFO would hang the read
    std::ifstream in(argument, std::ios::binary);
    if (!in) throw Error(argument, std::nullopt, "--polygon: neither WKT (POLYGON, MULTIPOLYGON) nor a readable file");
    try {
        return read_geojson_polygon(istream_json_source(in));
    } catch (const Error& e) {
        throw e.with_file(argument);
    }
}

}  // namespace lidarscout
