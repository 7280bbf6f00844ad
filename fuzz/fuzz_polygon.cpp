// libFuzzer target: the --polygon parsers (core/polygon): the input as WKT and as GeoJSON, and a
// polygon that parses is queried at its box's centre and outside its box (contains, touches_box,
// area). A lidarscout::Error is the expected outcome for bad input; a crash, another exception, a
// point outside the box found inside, a box not touched or a negative area is a bug.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "core/error.hpp"
#include "core/polygon.hpp"

namespace {

void query(const lidarscout::MultiPolygon& p) {
    if (!(p.area() >= 0)) std::abort();
    if (p.vertex_count() < 3 * p.polygon_count()) std::abort();
    const double cx = 0.5 * (p.min_x() + p.max_x()), cy = 0.5 * (p.min_y() + p.max_y());
    (void)p.contains(cx, cy);
    // Beyond the box by more than rounding (a coordinate of 1e51 absorbs "+ 1": the point is then a vertex).
    const auto beyond = [](double v, double sign) { return v + sign * std::max(1.0, std::abs(v) * 1e-6); };
    if (p.contains(beyond(p.min_x(), -1), beyond(p.min_y(), -1)) || p.contains(beyond(p.max_x(), 1), p.max_y()))
        std::abort();
    if (!p.touches_box(p.min_x(), p.min_y(), p.max_x(), p.max_y())) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    try {
        query(lidarscout::parse_wkt_polygon(text));
    } catch (const lidarscout::Error&) {
    }
    try {
        query(lidarscout::parse_geojson_polygon(text));
    } catch (const lidarscout::Error&) {
    }
    return 0;
}
