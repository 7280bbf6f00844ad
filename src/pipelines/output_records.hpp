// The records of a LAS/LAZ file written from other files' (clip, profile -o .laz, convert): COPC
// records dropped (the output is not a COPC file) and one CRS, written once in the form the output's
// point format expects: OGC WKT (global encoding bit 4) for point formats 6-10, GeoTIFF keys for
// formats 0-5 (WKT there only for a CRS without an EPSG code, on LAS 1.4). A record that states the
// CRS in another form (GeoTIFF keys beside the WKT, liblas's WKT copy) is dropped, so that no two
// records can disagree about where the points lie.
#pragma once

#include <string>
#include <vector>

#include "las/crs.hpp"
#include "las/header.hpp"
#include "las/vlr.hpp"

namespace lidarscout::pipelines {

// The COPC info VLR or hierarchy EVLR (user id "copc").
bool is_copc_record(const las::Vlr& v);

// Replaces every CRS record of `vlrs` and `evlrs` by `definition` (geo/crs_definition.hpp: "EPSG:h",
// "EPSG:h+v" or WKT) in the form the header's point format expects, and sets or clears the header's
// WKT bit to match. Throws Error (stage `stage`) when that form cannot name it: formats 0-5 of LAS
// 1.0-1.3 and a CRS without an EPSG code, or a CRS PROJ cannot write as WKT 1.
void write_crs(las::Header& h, std::vector<las::Vlr>& vlrs, std::vector<las::Vlr>& evlrs,
               const std::string& definition, const std::string& stage);

// Keeps the CRS the records say (`crs`, read from them) written once: the records of its form (the one
// read_crs used) as they are, those of any other form dropped, the WKT bit set to match; for point
// formats 6-10 a CRS stated by GeoTIFF keys is rewritten as WKT (write_crs). GeoTIFF keys without an
// EPSG code keep the WKT record the file has beside them (what names that CRS to PROJ), and liblas's
// copy of it when it is the only one. Records of a CRS that
// could not be read (crs.source "none") are left as they are (the WKT bit set for formats 6-10).
// Returns what changed, one note each.
std::vector<std::string> keep_crs(las::Header& h, std::vector<las::Vlr>& vlrs, std::vector<las::Vlr>& evlrs,
                                  const las::Crs& crs, const std::string& stage);

// keep_crs under the rule for what an output cannot hold: a CRS in GeoTIFF keys that point formats 6-10
// need as WKT and PROJ cannot write so is refused, an Error naming `file` (the input) and the fix, or with
// `force` left in its keys (the records and header as they were): then `forced` says so, for a warning.
std::vector<std::string> keep_crs_or_keys(las::Header& h, std::vector<las::Vlr>& vlrs, std::vector<las::Vlr>& evlrs,
                                          const las::Crs& crs, const std::string& stage, const std::string& file,
                                          bool force, std::string& forced);

}  // namespace lidarscout::pipelines
