// A STAC item of the plain shape, read straight from its JSON text (simdjson's validating DOM parser), for a
// country's catalog of 152,100 items (245 MB): read into a JSON document each and then looked at, reading it
// took 15,657 perf samples for two reads (bench_catalog), most of them the parse and the values built and freed;
// read this way, 8,592. The plain shape is what `lidarscout catalog` writes: type "Feature", a string id, one
// asset with a string href,
// properties with pc:count a whole number, proj:bbox 4 or 6 finite numbers with mins before maxes, and a CRS
// as a positive proj:epsg or a WKT2 text. Anything else (text that is not JSON, a field of another kind, a key
// written twice, several assets, a PROJJSON CRS, ...) is left to the general reader (dataset/stac_catalog.cpp),
// which reads every item and says what it cannot use: this one only goes faster where there is nothing to say.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>

namespace lidarscout::dataset {

struct PlainItem {
    std::string id;                             // "" when it has none
    std::string href;                           // the data asset's, as written
    std::optional<std::uint64_t> count;         // pc:count
    std::optional<std::array<double, 6>> bbox;  // proj:bbox (z NaN when 2D)
    std::string crs;                            // "EPSG:n" or the WKT2 text; "" when none
};

// proj:bbox's rule, shared with the general reader: 4 or 6 values (min x, y[, z], max x, y[, z]) into min x, y, z,
// max x, y, z (z NaN when 2D); nullopt for another count, or a min past its max. (The values are finite numbers.)
std::optional<std::array<double, 6>> proj_bbox(std::span<const double> values);

// The item `text` holds; nullopt when it is not JSON or not of the plain shape. `dropped`: the keys whose values
// the general reader drops wherever they lie (an asset under one of them is none). Safe from several threads.
std::optional<PlainItem> read_plain_item(std::string_view text, std::span<const std::string> dropped);

}  // namespace lidarscout::dataset
