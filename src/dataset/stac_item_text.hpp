// A STAC item of the plain shape, read straight from its JSON text (simdjson's validating DOM parser), for a
// country's catalog of 152,100 items: read into a JSON document each and then looked at, its items took 1.4 s
// of CPU (the parse, the values built and freed); read this way, a third of that. The plain shape is what
// `lidarscout catalog`, PDAL and QGIS write: type "Feature", a string id, one asset with a string href,
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

// The item `text` holds; nullopt when it is not JSON or not of the plain shape. `dropped`: the keys whose values
// the general reader drops wherever they lie (an asset under one of them is none). Safe from several threads.
std::optional<PlainItem> read_plain_item(std::string_view text, std::span<const std::string> dropped);

}  // namespace lidarscout::dataset
