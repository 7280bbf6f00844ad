// Whether an area's rings cross (core/polygon.hpp): a bow tie, a star drawn in one stroke, a hole
// crossing its outer ring. Such a polygon is still read -- a point is inside where an odd number of its
// rings enclose it (even-odd), and the parts of a multipolygon add up -- but what that covers may not be
// what was drawn, so a user is told, in one line naming a crossing.
//
// The check is a sweep of each part from west to east (Shamos-Hoey): the edges the sweep line meets
// kept in their order along it, each edge tested against its neighbours there as they change, so that
// the crossing met first is found for work of about n log n in the n vertices, whatever the shape (a
// star of 100k spikes meeting at its centre costs what a circle does). Only proper crossings count: a
// ring touching itself at a vertex, an edge ending on another, or edges along one line are not
// crossings (even-odd and union agree there). Parts of a multipolygon may overlap (their union is the
// region) and are checked each on its own.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

#include "core/polygon.hpp"

namespace lidarscout {

// Two edges of one part of a MultiPolygon that cross (each passes through the other's inside).
struct PolygonCrossing {
    std::size_t part = 0;                // the part (polygon) of the MultiPolygon, from 0
    std::size_t ring_a = 0, edge_a = 0;  // the rings in the part (0: the outer ring) and their edges
    std::size_t ring_b = 0, edge_b = 0;  // (edge k joins vertex k to vertex k + 1), a's ends before b's
    XY at;                               // where they cross
};

struct CrossingCheck {
    std::size_t parts = 0;                 // the polygons of the MultiPolygon
    std::optional<PolygonCrossing> first;  // the crossing the sweep met first (in the first part with one)
    std::uint64_t work = 0;                // sweep events and pairs of edges tested
};

// Looks for edges of one part that cross.
CrossingCheck find_crossing(const MultiPolygon& polygon);

// The line telling a user that the polygon `name` ("P.geojson", or "the --polygon WKT") crosses itself,
// where, and the rule applied; "" when no ring crosses.
std::string crossing_warning(const CrossingCheck& check, const std::string& name);

}  // namespace lidarscout
