// Whether an area's rings cross (core/polygon.hpp): a bow tie, a star drawn in one stroke, a hole
// crossing its outer ring. Such a polygon is still read -- a point is inside where an odd number of its
// rings enclose it (even-odd), and the parts of a multipolygon add up -- but what that covers may not be
// what was drawn, so a user is told, in one line naming the first crossing.
//
// The check costs about linear work in the vertices: the edges go into a grid of cells about the mean
// edge long (each edge in the cells its bounding box crosses, column by column), and only edges of the
// same part sharing a cell are tested against each other. Edges bunched together (a star of 100k
// spikes meeting at its centre) would cost pairs quadratic in the vertices: past a cap of work set by
// the vertex count alone (not by time), the check stops and says the polygon was not checked.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

#include "core/polygon.hpp"

namespace lidarscout {

// Two edges of one part of a MultiPolygon that cross (each passes through the other's inside: a
// touch at a vertex and edges along one line are not crossings).
struct PolygonCrossing {
    std::size_t part = 0;             // the part (polygon) of the MultiPolygon, from 0
    std::size_t ring_a = 0, edge_a = 0;  // the rings in the part (0: the outer ring) and their edges
    std::size_t ring_b = 0, edge_b = 0;  // (edge k joins vertex k to vertex k + 1), a before b
    XY at;                            // where they cross
};

struct CrossingCheck {
    bool checked = true;                    // false when the cap of work stopped it
    std::size_t parts = 0;                  // the polygons of the MultiPolygon
    std::optional<PolygonCrossing> first;   // the crossing of the lowest edges (ring by ring), if any
    std::uint64_t work = 0;                 // cells entered and pairs of edges tested
    std::uint64_t cap = 0;                  // the work allowed (from the vertex count)
};

// Looks for edges of one part that cross. The cap of work is 48 steps a vertex plus a million.
CrossingCheck find_crossing(const MultiPolygon& polygon);

// The line telling a user about the check of the polygon `name` ("P.geojson" or a WKT excerpt): where it
// crosses itself and the rule applied, or that it was not checked; "" when it was checked and no ring
// crosses.
std::string crossing_warning(const CrossingCheck& check, const std::string& name);

}  // namespace lidarscout
