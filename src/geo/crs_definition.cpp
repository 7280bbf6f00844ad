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

EpsgCodes epsg_codes_of_definition(const std::string& definition) {
    if (definition.size() < 6) return {};
    std::string prefix = definition.substr(0, 5);
    for (char& c : prefix) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    if (prefix != "EPSG:") return {};
    EpsgCodes codes;
    const char* end = definition.data() + definition.size();
    const auto [ptr, ec] = std::from_chars(definition.data() + 5, end, codes.horizontal);
    if (ec != std::errc() || codes.horizontal <= 0) return {};
    if (ptr == end) return codes;
    if (*ptr != '+') return {};
    const auto [vptr, vec] = std::from_chars(ptr + 1, end, codes.vertical);
    if (vec != std::errc() || vptr != end || codes.vertical <= 0) return {};
    return codes;
}

int epsg_of_definition(const std::string& definition) {
    const EpsgCodes codes = epsg_codes_of_definition(definition);
    return codes.vertical ? 0 : codes.horizontal;
}

}  // namespace lidarscout::geo
