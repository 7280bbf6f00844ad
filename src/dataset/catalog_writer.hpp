// Writing a dataset as a QGIS virtual point cloud (.vpc): a STAC ItemCollection with an item
// per tile, carrying what QGIS and PDAL wrench read -- the data asset's href (relative to the
// .vpc's folder for local files, "./name"; URLs as they are), pc:count, pc:type, pc:encoding,
// pc:schemas, proj:bbox and proj:geometry in the tile's CRS, proj:wkt2 (and proj:epsg when the
// CRS has one), the WGS 84 bbox and geometry STAC requires, and the acquisition date (the
// header's creation day; when it has none, datetime null between 1970 and the day of writing,
// as STAC allows). read_catalog (stac_catalog.hpp) reads it back.
#pragma once

#include <cstddef>
#include <string>

#include "dataset/dataset.hpp"

namespace lidarscout::dataset {

struct CatalogWriteResult {
    std::size_t items = 0;
    std::size_t without_crs = 0;  // tiles whose CRS is unknown: no proj: CRS nor WGS 84 footprint of their own
};

// Writes `dataset` to `output` (through a temporary name, never over an input). Throws
// lidarscout::Error for a virtual replica's tile (its shift cannot be written in a catalog) or
// when the file cannot be written.
CatalogWriteResult write_catalog(const Dataset& dataset, const std::string& output);

}  // namespace lidarscout::dataset
