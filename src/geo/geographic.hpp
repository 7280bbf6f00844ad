// Coordinates in degrees (longitude, latitude) as a user meets them: whether four numbers look like
// degrees (a hint when they are given to data in metres or feet), and the UTM zone to reproject
// degrees into (a hint naming the --crs to give). Pure arithmetic: nothing here calls PROJ.
#pragma once

#include <string>

namespace lidarscout::geo {

// Whether the box xmin,ymin,xmax,ymax could be longitude/latitude: |x| <= 360 and |y| <= 90.
bool looks_like_degrees(double min_x, double min_y, double max_x, double max_y);

// The WGS 84 / UTM zone around a longitude/latitude: its definition and a name for people.
struct UtmZone {
    std::string crs;   // "EPSG:32610" (north), "EPSG:32710" (south)
    std::string name;  // "WGS 84 / UTM zone 10N"
};
// Longitudes are taken modulo 360; latitudes are clamped to [-80, 84] (UTM's extent).
UtmZone utm_zone_at(double lon, double lat);

}  // namespace lidarscout::geo
