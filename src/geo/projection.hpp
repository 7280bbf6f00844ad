// Coordinate reference systems through PROJ (Debian libproj-dev): what a CRS definition
// (crs_definition.hpp, or a user's "EPSG:n") means — its WKT and its units —, transforms of
// coordinates between two CRSs in their native units (feet stay feet), and bounds in
// longitude/latitude. Every PROJ call of the project is in projection.cpp.
//
// Thread safety: a CrsTransform may be used from several threads at once (each call locks it;
// pass many points per call). Errors are lidarscout::Error in stage "geo".
#pragma once

#include <memory>
#include <span>
#include <string>

#include "las/crs.hpp"

namespace lidarscout::geo {

// What PROJ says about a CRS definition.
struct CrsInfo {
    std::string name;             // "NAD83 / Kentucky Single Zone (ftUS)"
    std::string wkt;              // WKT2 (2019), what GDAL and QGIS read
    double xy_to_metres = 1.0;    // native horizontal unit -> metres (0.3048006 for US feet)
    double z_to_metres = 1.0;     // the vertical CRS's unit, else the horizontal one
    bool geographic = false;      // x/y are degrees
    bool has_vertical = false;    // a compound CRS with a vertical part
};

// Throws Error (stage "geo") when PROJ does not understand `definition`. Kept per definition (the last 64
// asked), as a catalog's thousands of tiles share a few CRSs.
CrsInfo crs_info(const std::string& definition);
// How many definitions crs_info asked PROJ about so far (each opening its database).
std::size_t crs_infos_made();

// The OGC WKT 1 (GDAL's flavour, what LAS 1.4's WKT records hold) of `definition`. Throws Error
// (stage "geo") when PROJ does not understand it or cannot write it as WKT 1.
std::string crs_wkt1(const std::string& definition);

// Whether PROJ understands `definition` as a CRS (answers kept per definition).
bool proj_knows_crs(const std::string& definition);

// A compound EPSG CRS whose vertical part PROJ lacks (EPSG:2903+5103) while it knows the
// horizontal one is used by its horizontal part alone: crs.vertical_usable is set false (so that
// crs_definition names EPSG:h) and a warning is added to crs.warnings. Any other CRS is left as
// it is (a CRS PROJ does not know at all is reported where it is used).
void fall_back_to_horizontal(las::Crs& crs);
// The warning of that fallback for `crs` ("" when its vertical CRS is used).
std::string vertical_fallback_message(const las::Crs& crs);

// Longitude/latitude (degrees, WGS 84) bounds.
struct LonLatBounds {
    double west = 0, south = 0, east = 0, north = 0;
};

class CrsTransform {
public:
    // From `source` to `target` (definitions as crs_info takes). Throws Error when PROJ finds
    // no transformation.
    CrsTransform(const std::string& source, const std::string& target);
    ~CrsTransform();
    CrsTransform(const CrsTransform&) = delete;
    CrsTransform& operator=(const CrsTransform&) = delete;

    const std::string& source() const { return source_; }
    const std::string& target() const { return target_; }
    // Whether heights are transformed too: both CRSs are compound (horizontal + vertical), so a
    // z given to apply() moves from the source's vertical datum and unit to the target's.
    bool transforms_heights() const { return heights_; }
    // The name of the operation PROJ uses at (x, y, z) (source units) when it is only a
    // "ballpark" one: no datum shift, accuracy unknown, usually because a grid is not installed.
    // Empty when the operation is a real one.
    std::string ballpark_at(double x, double y, double z) const;

    // Transforms points in place, native units of source -> native units of target (x east,
    // y north whatever the CRS's axis order). z may be empty (taken as 0, left alone).
    // Throws Error when a point cannot be transformed (outside the CRS's domain).
    void apply(std::span<double> x, std::span<double> y, std::span<double> z) const;
    void apply(double& x, double& y, double& z) const;
    // The box [min_x, max_x] x [min_y, max_y] in source units transformed to target units,
    // densified along its edges so that curved edges are enclosed.
    void apply_bounds(double& min_x, double& min_y, double& max_x, double& max_y) const;

private:
    struct State;
    std::string source_, target_;
    bool heights_ = false;
    std::unique_ptr<State> state_;
};

// The lon/lat bounds of a box in `definition`'s native units.
LonLatBounds lonlat_bounds(const std::string& definition, double min_x, double min_y, double max_x, double max_y);
// How many lon/lat transforms lonlat_bounds made so far (each a search of PROJ's database); the
// tiles of a survey that share a CRS share one.
std::size_t lonlat_transforms_made();

}  // namespace lidarscout::geo
