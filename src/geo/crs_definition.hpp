// The text PROJ and GDAL accept for a tile's CRS ("EPSG:3089", "EPSG:2154+5720" for a compound
// horizontal + vertical CRS, or the file's own WKT), built from what las::read_crs found. Pure
// string logic: nothing here calls PROJ.
#pragma once

#include <string>

#include "las/crs.hpp"

namespace lidarscout::geo {

// "EPSG:h" or "EPSG:h+v" when the horizontal EPSG code is known (the vertical one when usable),
// else the file's WKT, else "" (no usable CRS). A vertical code without a horizontal one gives ""
// (nothing to place x/y by).
std::string crs_definition(const las::Crs& crs);

// "EPSG:3089" -> 3089 for a definition that is exactly "EPSG:n" (any case), else 0.
int epsg_of_definition(const std::string& definition);

// "EPSG:h" -> {h, 0}, "EPSG:h+v" -> {h, v} (any case); {0, 0} for anything else.
struct EpsgCodes {
    int horizontal = 0, vertical = 0;
};
EpsgCodes epsg_codes_of_definition(const std::string& definition);

}  // namespace lidarscout::geo
