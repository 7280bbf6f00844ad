// CRS records for a file being written (LASF_Projection VLRs): recognising a file's CRS records and
// their form (to keep one form and drop the others), the GeoTIFF key directory of an EPSG code and
// the OGC WKT record. las/crs.hpp reads them.
#pragma once

#include <string>

#include "las/vlr.hpp"

namespace lidarscout::las {

// How a record states a CRS: GeoTIFF keys (LASF_Projection 34735-34737), OGC WKT (LASF_Projection
// 2112, and 2111, a math transform as WKT), liblas's copy of the WKT (liblas 2112, "OGR variant of
// OpenGIS WKT SRS", which read_crs does not read), or no CRS record.
enum class CrsForm { None, GeoTiff, Wkt, LiblasWkt };
CrsForm crs_record_form(const Vlr& v);
// Whether `v` is a CRS record of any form.
bool is_crs_record(const Vlr& v);
// The GeoTIFF key directory (34735) of the CRS EPSG:`epsg` in its own units: projected, or
// geographic (GTModelType 2, GeographicType) when `geographic`; compound with EPSG:`vertical_epsg`
// when that is not 0.
Vlr geotiff_epsg_vlr(int epsg, int vertical_epsg = 0, bool geographic = false);
// The OGC WKT record (2112) holding `wkt`, NUL-terminated.
Vlr wkt_vlr(const std::string& wkt);

}  // namespace lidarscout::las
