// Writing a dataset as a QGIS virtual point cloud (.vpc): a STAC ItemCollection with an item
// per tile, carrying what QGIS and PDAL wrench read -- the data asset's href (relative to the
// .vpc's folder for local files, "./name"; URLs as they are), pc:count, pc:type, pc:encoding,
// pc:schemas, proj:bbox and proj:geometry in the tile's CRS, proj:wkt2 (and proj:epsg when the
// CRS has one), the WGS 84 bbox and geometry STAC requires, and the acquisition date (the
// header's creation day; when it has none, datetime null between 1970 and the day of writing,
// as STAC allows). read_catalog (stac_catalog.hpp) reads it back.
#pragma once

#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include "dataset/dataset.hpp"

namespace lidarscout::dataset {

struct CatalogWriteResult {
    std::size_t items = 0;
    std::size_t without_crs = 0;  // tiles whose CRS is unknown: no proj: CRS nor WGS 84 footprint of their own
    std::vector<std::string> ids;  // each tile's item id, in the dataset's order
};

struct CatalogWriteOptions {
    // The path each tile is named by (empty: their files'): a virtual replica's tiles, which share their
    // source's file, are named where `synth replicate` without --virtual would write them.
    std::vector<std::string> paths;
    std::string overview;  // the overview sidecar to name in a top-level link (kOverviewRel); "" none
};

// The item id of each tile (unique: a file name's stem, with "-2", "-3"... when it repeats).
std::vector<std::string> catalog_ids(const Dataset& dataset, const CatalogWriteOptions& options = {});

// Writes `dataset` to `output` (through a temporary name, never over an input). Throws
// lidarscout::Error when tiles share a path (a virtual replica's, without options.paths) or
// when the file cannot be written.
CatalogWriteResult write_catalog(const Dataset& dataset, const std::string& output,
                                 const CatalogWriteOptions& options = {});

// The paths of a virtual replica's tiles for CatalogWriteOptions::paths: each named tile of `sources`
// (the sources the dataset was opened from, TileSource::name) in `folder`, the others' own; empty
// when no source has a name.
std::vector<std::string> catalog_paths(const Dataset& dataset, std::span<const TileSource> sources,
                                       const std::string& folder);

}  // namespace lidarscout::dataset
