// MultiPolygon: the even-odd test with points on edges inside, and the WKT and GeoJSON parsers.
#include "core/polygon.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>

#include "core/error.hpp"
#include "core/json_reader.hpp"
#include "core/text.hpp"

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

// Whether (x, y) lies on the segment a-b (exactly: the cross product is zero within the segment's box).
bool on_segment(const XY& a, const XY& b, double x, double y) {
    if (x < std::min(a.x, b.x) || x > std::max(a.x, b.x) || y < std::min(a.y, b.y) || y > std::max(a.y, b.y)) {
        return false;
    }
    return (b.x - a.x) * (y - a.y) - (b.y - a.y) * (x - a.x) == 0.0;
}

// Whether a horizontal ray from (x, y) towards +x crosses a-b (half-open in y, so a vertex counts once).
bool crosses(const XY& a, const XY& b, double x, double y) {
    if ((a.y > y) == (b.y > y)) return false;
    const double t = (y - a.y) / (b.y - a.y);
    return x < a.x + t * (b.x - a.x);
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

double ring_area(const Ring& r) {
    double twice = 0;
    for (std::size_t i = 0, j = r.size() - 1; i < r.size(); j = i++) twice += r[j].x * r[i].y - r[i].x * r[j].y;
    return std::abs(twice) / 2;
}

}  // namespace

MultiPolygon::MultiPolygon(std::vector<std::vector<Ring>> polygons) {
    if (polygons.empty()) throw polygon_error("the polygon has no rings");
    min_x_ = min_y_ = INFINITY;
    max_x_ = max_y_ = -INFINITY;
    for (auto& rings : polygons) {
        if (rings.empty()) throw polygon_error("a polygon has no outer ring");
        for (auto& ring : rings) {
            ring = closed_ring(std::move(ring));
            for (const XY& v : ring) {
                min_x_ = std::min(min_x_, v.x), max_x_ = std::max(max_x_, v.x);
                min_y_ = std::min(min_y_, v.y), max_y_ = std::max(max_y_, v.y);
            }
        }
    }
    polygons_ = std::move(polygons);
}

bool MultiPolygon::contains(double x, double y) const {
    if (!(x >= min_x_ && x <= max_x_ && y >= min_y_ && y <= max_y_)) return false;
    bool inside = false;
    for (const auto& rings : polygons_) {
        for (const Ring& r : rings) {
            for (std::size_t i = 0, j = r.size() - 1; i < r.size(); j = i++) {
                if (on_segment(r[j], r[i], x, y)) return true;
                if (crosses(r[j], r[i], x, y)) inside = !inside;
            }
        }
    }
    return inside;
}

bool MultiPolygon::touches_box(double x0, double y0, double x1, double y1) const {
    if (x0 > max_x_ || x1 < min_x_ || y0 > max_y_ || y1 < min_y_) return false;
    if (contains(x0, y0)) return true;  // the box inside the polygon (or a corner on it)
    for (const auto& rings : polygons_) {
        for (const Ring& r : rings) {
            for (std::size_t i = 0, j = r.size() - 1; i < r.size(); j = i++) {
                if (segment_meets_box(r[j], r[i], x0, y0, x1, y1)) return true;  // crossing, or inside the box
            }
        }
    }
    return false;
}

double MultiPolygon::area() const {
    double a = 0;
    for (const auto& rings : polygons_) {
        for (std::size_t k = 0; k < rings.size(); ++k) a += (k == 0 ? 1 : -1) * ring_area(rings[k]);
    }
    return a;
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
    std::ifstream in(argument, std::ios::binary);
    if (!in) throw Error(argument, std::nullopt, "--polygon: neither WKT (POLYGON, MULTIPOLYGON) nor a readable file");
    try {
        return read_geojson_polygon(istream_json_source(in));
    } catch (const Error& e) {
        throw e.with_file(argument);
    }
}

}  // namespace lidarscout
