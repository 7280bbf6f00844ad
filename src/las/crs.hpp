// The coordinate reference system (CRS) and linear units of a LAS/LAZ file, read from its
// GeoTIFF keys (LASF_Projection 34735/34736/34737) or its OGC WKT (LASF_Projection 2112, VLR
// or EVLR; WKT1 and WKT2). We report what the file says, even when it is wrong; we do not
// reproject and do not consult a CRS database beyond a built-in table of EPSG units.
//
// Malformed CRS records never throw: the CRS is metadata that the points do not need, so a
// bad key (a count past the payload, an offset beyond GeoDoubleParams/GeoAsciiParams, a
// value of the wrong type), an unparseable WKT or an oversized record is ignored and
// described in Crs::warnings. Only I/O errors while loading an EVLR payload propagate.
#pragma once

#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/diagnostic.hpp"
#include "las/vlr.hpp"

namespace lidarscout::io {
class File;
}

namespace lidarscout::las {

enum class LinearUnit { Unknown, Metre, InternationalFoot, UsSurveyFoot, Other };

inline constexpr double kFootMetres = 0.3048;                 // international foot
inline constexpr double kUsSurveyFootMetres = 1200.0 / 3937.0;  // US survey foot

// "metre", "foot", "us_survey_foot", "other" or "unknown".
const char* unit_name(LinearUnit unit);
// Metres per unit: 1, 0.3048, 1200/3937; NaN for Unknown and Other (Other carries its own).
double unit_to_metres(LinearUnit unit);

struct Crs {
    std::string source = "none";  // where the answer came from: "geotiff", "wkt" or "none"
    std::optional<int> epsg;            // horizontal (projected or geographic) CRS
    std::optional<int> vertical_epsg;   // vertical CRS
    // False when the vertical CRS cannot be used (geo::fall_back_to_horizontal: PROJ lacks it):
    // the CRS then stands for its horizontal part alone, heights as stored.
    bool vertical_usable = true;
    std::string name;                   // citation / WKT name, as written
    bool geographic = false;            // x/y are angles (degrees), so no linear unit applies
    LinearUnit horizontal_unit = LinearUnit::Unknown;
    LinearUnit vertical_unit = LinearUnit::Unknown;
    double horizontal_to_metres = std::numeric_limits<double>::quiet_NaN();
    double vertical_to_metres = std::numeric_limits<double>::quiet_NaN();
    std::string horizontal_unit_name;   // as written in the WKT, or the canonical name
    std::string vertical_unit_name;
    std::string wkt;                    // the file's WKT text, when it has a WKT record
    Diagnostics warnings;               // malformed or contradictory records, in file order

    // Metres per z unit: the vertical unit when the file gives one, else the horizontal one
    // (the usual convention when no vertical unit is recorded); NaN when neither is known.
    double z_to_metres() const;
};

// Reads the CRS of a file from its VLRs and EVLRs (EVLR payloads that were not loaded are
// read from `file`). `wkt_flag` is bit 4 of the header's global encoding: when set the WKT
// record is authoritative, otherwise the GeoTIFF keys are; the other one is the fallback,
// and disagreements between the two are reported as warnings.
Crs read_crs(const std::vector<Vlr>& vlrs, const std::vector<Vlr>& evlrs, const io::File& file,
             bool wkt_flag = false);

// The two parsers behind read_crs, on raw payloads (empty spans for absent records). Each
// returns source "geotiff"/"wkt" on success; source "none" when there is nothing usable.
Crs parse_geotiff_crs(std::span<const std::uint8_t> key_directory, std::span<const std::uint8_t> double_params,
                      std::span<const std::uint8_t> ascii_params);
Crs parse_wkt_crs(std::string_view wkt);

// Units of EPSG codes known to the built-in table (all projected CRSs of the EPSG registry in
// US survey feet or international feet, common metre families, common vertical CRSs);
// Unknown for codes not in the table.
LinearUnit projected_unit_of_epsg(int code);
LinearUnit vertical_unit_of_epsg(int code);

}  // namespace lidarscout::las
