// A tile = one LAS/LAZ file: everything the overview needs from it without touching the
// point data: header, VLRs/EVLRs, CRS and units, LAZ description, chunk table, COPC info.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/diagnostic.hpp"
#include "las/copc.hpp"
#include "las/crs.hpp"
#include "las/header.hpp"
#include "las/laszip_vlr.hpp"
#include "las/vlr.hpp"
#include "laz/chunk_table.hpp"

namespace lidarscout::io {
class File;
}

namespace lidarscout::dataset {

struct Tile {
    std::string path;
    std::uint64_t file_size = 0;
    las::Header header;
    std::vector<las::Vlr> vlrs;
    std::vector<las::Vlr> evlrs;
    las::Crs crs;
    std::optional<las::LaszipVlr> laz;      // set for compressed files
    std::optional<laz::ChunkTable> chunks;  // set for LAZ files (empty for compressor 1: see laz::decode_units)
    std::optional<las::CopcInfo> copc;
    Diagnostics warnings;  // oddities that did not stop reading (shown by `info`)

    bool compressed() const { return laz.has_value(); }
};

struct TileOptions {
    bool chunk_table = true;  // read (and validate) the LAZ chunk table
};

// Reads the tile's metadata; throws lidarscout::Error (file, offset, cause) on bad input.
Tile read_tile(const io::File& file, const TileOptions& options = {});

}  // namespace lidarscout::dataset
