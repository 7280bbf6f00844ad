// looks_like_degrees and utm_zone_at: the 60 zones of 6 degrees from 180 W, north and south of
// the equator (EPSG 326zz and 327zz).
#include "geo/geographic.hpp"

#include <algorithm>
#include <cmath>

namespace lidarscout::geo {

bool looks_like_degrees(double min_x, double min_y, double max_x, double max_y) {
    return std::max(std::abs(min_x), std::abs(max_x)) <= 360 && std::max(std::abs(min_y), std::abs(max_y)) <= 90;
}

UtmZone utm_zone_at(double lon, double lat) {
    const double wrapped = std::fmod(std::fmod(lon + 180.0, 360.0) + 360.0, 360.0);  // [0, 360) from 180 W
    const int zone = std::clamp(static_cast<int>(wrapped / 6.0) + 1, 1, 60);
    const bool north = std::clamp(lat, -80.0, 84.0) >= 0;
    const std::string number = (zone < 10 ? "0" : "") + std::to_string(zone);
    return {"EPSG:32" + std::string(north ? "6" : "7") + number,
            "WGS 84 / UTM zone " + std::to_string(zone) + (north ? "N" : "S")};
}

}  // namespace lidarscout::geo
