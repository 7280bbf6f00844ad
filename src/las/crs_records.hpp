// CRS records for a file being written (LASF_Projection VLRs): recognising a file's CRS records (to
// drop them), the GeoTIFF key directory of an EPSG code and the OGC WKT record. las/crs.hpp reads them.
#pragma once

#include <string>

#include "las/vlr.hpp"

namespace lidarscout::las {

// Whether `v` is a CRS record: GeoTIFF keys (34735-34737) or WKT (2111 math transform, 2112 CRS).
bool is_crs_record(const Vlr& v);
// The GeoTIFF key directory (34735) of the projected CRS EPSG:`epsg` in its own units, compound with
// EPSG:`vertical_epsg` when that is not 0.
Vlr geotiff_epsg_vlr(int epsg, int vertical_epsg = 0);
// The OGC WKT record (2112) holding `wkt`, NUL-terminated.
Vlr wkt_vlr(const std::string& wkt);

}  // namespace lidarscout::las
