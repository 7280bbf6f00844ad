// A tile = one LAS/LAZ file: everything the overview needs from it without touching the
// point data: header, VLRs/EVLRs, CRS and units, LAZ description, chunk table, COPC info.
//
// A dataset holds 100,000s of tiles, so a tile keeps little of its own: its header and COPC
// info (what a virtual replica moves) by value, and the rest of what its file says behind a
// shared pointer to immutable parts: a TileFile per file (the tiles of a virtual replica made
// from one source share their source's), and in it the file's records (VLRs, EVLRs, CRS,
// LASzip VLR), which tiles with alike records (a survey's, written by one tool) may share too
// (SharedRecords). Read the parts through the accessors; dataset/metadata.hpp counts the bytes.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "core/diagnostic.hpp"
#include "geo/projection.hpp"
#include "las/copc.hpp"
#include "las/crs.hpp"
#include "las/header.hpp"
#include "las/laszip_vlr.hpp"
#include "las/vlr.hpp"
#include "laz/laz.hpp"

namespace lidarscout::io {
class File;
}

namespace lidarscout::dataset {

// What a file's VLRs and EVLRs say.
struct TileRecords {
    std::vector<las::Vlr> vlrs;
    std::vector<las::Vlr> evlrs;
    las::Crs crs;
    std::optional<las::LaszipVlr> laz;  // set for compressed files
};

// What a file was when it was looked at: its size and validator ("mtime NS" for a local file, the
// server's ETag or Last-Modified for a URL: dataset/overview_sidecar.hpp, file_validator).
struct FileValidator {
    std::uint64_t size = 0;
    std::string tag;
    bool operator==(const FileValidator&) const = default;
};

// What an overview sidecar says of a tile it placed (dataset/overview_sidecar.hpp): the file it was
// made from, and its chunk points' records in the tile's own format (none when the sidecar holds none).
class OverviewDecoding;
struct TileOverview {
    FileValidator made_from;
    // A block of the sidecar's, shared by its tiles; emptied by OverviewRelease once their reader took them.
    std::shared_ptr<std::vector<std::uint8_t>> records;
    std::size_t first = 0, count = 0;                          // this tile's: records [first, first + count)
    std::shared_ptr<const OverviewDecoding> decoding;  // the records' decoding, where it went on (null: they are in)
};

// What a tile's file says besides its header and COPC info.
struct TileFile {
    std::string path;
    std::uint64_t file_size = 0;
    std::shared_ptr<const TileRecords> records;  // never null in a tile read by read_tile
    std::optional<laz::ChunkTable> chunks;  // set for LAZ files (empty for compressor 1: see laz::decode_units)
    Diagnostics warnings;  // oddities that did not stop reading (shown by `info`)
    std::shared_ptr<const TileOverview> overview;  // set for a tile placed from an overview sidecar
};

struct Tile {
    las::Header header;                 // the file's (a virtual replica tile's: moved, see shift_tile)
    std::optional<las::CopcInfo> copc;  // likewise
    std::shared_ptr<const TileFile> file;  // never null in a tile read by read_tile

    const std::string& path() const { return file->path; }
    std::uint64_t file_size() const { return file->file_size; }
    const std::vector<las::Vlr>& vlrs() const { return file->records->vlrs; }
    const std::vector<las::Vlr>& evlrs() const { return file->records->evlrs; }
    const las::Crs& crs() const { return file->records->crs; }
    const std::optional<las::LaszipVlr>& laz() const { return file->records->laz; }
    const std::optional<laz::ChunkTable>& chunks() const { return file->chunks; }
    const Diagnostics& warnings() const { return file->warnings; }
    bool compressed() const { return laz().has_value(); }
};

// Records read once for all the tiles whose records are alike (a survey's tiles, written by one
// tool, mostly have the same VLRs): read_tile hands its records to intern() and keeps what it
// returns. Safe to share between reader threads.
class SharedRecords {
public:
    // An equal TileRecords given before, else `records` (kept for the next). Records are what the
    // VLRs, EVLRs and the header's WKT bit say (las::read_crs, the LASzip VLR), but for the file
    // their CRS warnings name: records are equal when those inputs are, and their CRS warnings and
    // LASzip VLRs too. Records with an EVLR whose payload was not loaded (read_crs may have read it
    // from the file) are never shared.
    std::shared_ptr<const TileRecords> intern(std::shared_ptr<const TileRecords> records, bool wkt_flag);
    // Records given before with these VLRs, EVLRs (payloads loaded) and WKT bit whose CRS came without a warning
    // (then the CRS read from these inputs is theirs); null when none.
    std::shared_ptr<const TileRecords> find(const std::vector<las::Vlr>& vlrs, const std::vector<las::Vlr>& evlrs,
                                            bool wkt_flag) const;
    // How many distinct records are held.
    std::size_t size() const;

private:
    struct Entry {
        std::shared_ptr<const TileRecords> records;
        bool wkt_flag = false;
    };
    // With mutex_ held: the records held for these inputs that `alike` accepts; null when none.
    std::shared_ptr<const TileRecords> held_alike(const std::vector<las::Vlr>& vlrs,
                                                  const std::vector<las::Vlr>& evlrs, bool wkt_flag,
                                                  const std::function<bool(const TileRecords&)>& alike) const;

    mutable std::mutex mutex_;
    std::unordered_multimap<std::size_t, Entry> entries_;  // by a hash of the VLRs and EVLRs
};

struct TileOptions {
    bool chunk_table = true;  // read (and validate) the LAZ chunk table
    SharedRecords* shared_records = nullptr;  // when set, the tile's records are shared through it
    std::shared_ptr<const TileOverview> overview;  // kept in the tile's TileFile
};

// Reads the tile's metadata; throws lidarscout::Error (file, offset, cause) on bad input.
Tile read_tile(const io::File& file, const TileOptions& options = {});

// The tile's header bounds in longitude/latitude (WGS 84) through PROJ; empty when its CRS is
// unknown, it has no points, or PROJ cannot transform them.
std::optional<geo::LonLatBounds> tile_lonlat_bounds(const Tile& tile);

}  // namespace lidarscout::dataset
