// MultiPolygon: the union of even-odd polygons with points on edges inside, tested through an index of
// the edges by bands of y; and the WKT and GeoJSON parsers.
#include "core/polygon.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
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
// Branch-free: in a crowded band these outcomes are unpredictable.
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

// The index names vertices, and counts its entries, in 32 bits: about 4 entries per edge at most.
constexpr std::size_t kMaxVertices = std::numeric_limits<std::uint32_t>::max() / 8;

// How many bands: one per edge at most, and fewer when the edges' y-spans add up to more than 2
// polygon heights, so that bands times summed spans (in heights) stays within 2 edges. An edge meets
// at most its span in bands plus 2, so the index holds at most about 4 entries per edge.
std::size_t band_count(std::size_t edges, double summed_spans, double height) {
    if (!(height > 0) || !std::isfinite(height) || !std::isfinite(summed_spans)) return 1;
    const double n = static_cast<double>(edges), bands = std::min(n, 2 * n / std::max(summed_spans / height, 2.0));
    return std::max<std::size_t>(1, static_cast<std::size_t>(bands));
}

// Calls fn with each edge's first vertex: ring r's edges start at ring_starts[r] .. ring_starts[r + 1] - 2.
template <typename Fn>
void for_each_edge(std::span<const std::uint32_t> ring_starts, Fn&& fn) {
    for (std::size_t r = 0; r + 1 < ring_starts.size(); ++r) {
        for (std::uint32_t i = ring_starts[r]; i + 1 < ring_starts[r + 1]; ++i) fn(i);
    }
}

}  // namespace

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

// Counts each band's edges, then lists them (edges in ascending order, so each band is sorted).
void MultiPolygon::build_index() {
    double spans = 0;
    for_each_edge(ring_starts_, [&](std::uint32_t i) { spans += std::abs(vertices_[i + 1].y - vertices_[i].y); });
    std::size_t bands = band_count(vertex_count(), spans, max_y_ - min_y_);
    band_scale_ = static_cast<double>(bands) / (max_y_ - min_y_);
    if (bands == 1 || !std::isfinite(band_scale_)) bands = 1, band_scale_ = 0;
    band_starts_.assign(bands + 1, 0);
    const auto bands_of = [&](std::uint32_t i) {
        const auto [lo, hi] = std::minmax(vertices_[i].y, vertices_[i + 1].y);
        return std::pair{band_of(lo), band_of(hi)};
    };
    for_each_edge(ring_starts_, [&](std::uint32_t i) {
        for (auto [b, last] = bands_of(i); b <= last; ++b) ++band_starts_[b + 1];
    });
    for (std::size_t b = 1; b <= bands; ++b) band_starts_[b] += band_starts_[b - 1];
    std::vector<std::uint32_t> next(band_starts_.begin(), band_starts_.end() - 1);
    band_edges_.resize(band_starts_.back());
    for_each_edge(ring_starts_, [&](std::uint32_t i) {
        for (auto [b, last] = bands_of(i); b <= last; ++b) band_edges_[next[b]++] = i;
    });
}

std::size_t MultiPolygon::band_of(double y) const {
    const double b = std::floor((y - min_y_) * band_scale_);
    if (!(b > 0)) return 0;  // also NaN
    const std::size_t last = band_starts_.size() - 2;
    return b >= static_cast<double>(last) ? last : static_cast<std::size_t>(b);
}

std::span<const std::uint32_t> MultiPolygon::band(std::size_t b) const {
    return std::span(band_edges_).subspan(band_starts_[b], band_starts_[b + 1] - band_starts_[b]);
}

bool MultiPolygon::contains(double x, double y) const {
    if (band_starts_.empty() || !in_box(x, y)) return false;
    std::uint32_t polygon_end = 0;
    bool inside = false;  // in the polygon whose edges are being read
    for (const std::uint32_t i : band(band_of(y))) {
        if (i >= polygon_end) {  // the first edge of a later polygon: the previous one is decided
            if (inside) return true;
            polygon_end = *std::upper_bound(polygon_starts_.begin(), polygon_starts_.end(), i);
        }
        const XY &a = vertices_[i], &b = vertices_[i + 1];
        const double c = cross(a, b, x, y);
        if (c == 0 && within(a, b, x, y)) return true;  // on the edge
        inside = inside != crossed(a, b, y, c);
    }
    return inside;
}

std::size_t MultiPolygon::edges_examined(double x, double y) const {
    return band_starts_.empty() || !in_box(x, y) ? 0 : band(band_of(y)).size();
}

bool MultiPolygon::touches_box(double x0, double y0, double x1, double y1) const {
    if (band_starts_.empty() || x0 > max_x_ || x1 < min_x_ || y0 > max_y_ || y1 < min_y_) return false;
    if (contains(x0, y0)) return true;  // the box inside the polygon (or a corner on it)
    for (std::size_t b = band_of(std::max(y0, min_y_)), last = band_of(std::min(y1, max_y_)); b <= last; ++b) {
        for (const std::uint32_t i : band(b)) {  // crossing the box, or inside it
            if (segment_meets_box(vertices_[i], vertices_[i + 1], x0, y0, x1, y1)) return true;
        }
    }
    return false;
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

std::size_t MultiPolygon::held_bytes() const {
    const std::size_t numbers = ring_starts_.capacity() + polygon_starts_.capacity() + band_starts_.capacity() +
                                band_edges_.capacity();
    return vertices_.capacity() * sizeof(XY) + numbers * sizeof(std::uint32_t);
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
