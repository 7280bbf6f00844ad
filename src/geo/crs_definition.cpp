// crs_definition: EPSG codes first (PROJ's database knows their units and axes), WKT second.
#include "geo/crs_definition.hpp"

#include <cctype>
#include <charconv>

namespace lidarscout::geo {

std::string crs_definition(const las::Crs& crs) {
    if (crs.epsg) {
        std::string def = "EPSG:" + std::to_string(*crs.epsg);
        if (crs.vertical_epsg && crs.vertical_usable) def += "+" + std::to_string(*crs.vertical_epsg);
        return def;
    }
    return crs.wkt;
}

int epsg_of_definition(const std::string& definition) {
    if (definition.size() < 6) return 0;
    std::string prefix = definition.substr(0, 5);
    for (char& c : prefix) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    if (prefix != "EPSG:") return 0;
    int code = 0;
    const char* end = definition.data() + definition.size();
    const auto [ptr, ec] = std::from_chars(definition.data() + 5, end, code);
    return ec == std::errc() && ptr == end && code > 0 ? code : 0;
}

}  // namespace lidarscout::geo
