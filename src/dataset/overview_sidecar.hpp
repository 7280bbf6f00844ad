// The overview sidecar of a catalog (`lidarscout catalog ... -o OUT.vpc --overview` writes
// OUT.overview.laz beside OUT.vpc; the VPC names it in a top-level link of rel kOverviewRel): the
// chunk points of every tile and what places and decodes each tile without touching it, read in a few
// large reads, so that opening a country-sized remote catalog asks its tiles for nothing.
//
// Layout: a LAS 1.4 LAZ file (any LAZ reader reads its points).
// - Points: every tile's chunk points (dataset/chunk_points.hpp), in the format of the tiles (their
//   most common point format, record length and scale; tiles of another kind hold none there) plus
//   one extra bytes field "tile" (u32, described in the Extra Bytes VLR): the tile's index in the
//   table below. A tile's points lie together, the tiles ordered along a Hilbert curve over their
//   centres, so that the tiles of a view are a few contiguous ranges. Coordinates use the scale of
//   the tiles and the offset of one of them: a tile's raw X/Y/Z are the sidecar's minus its integer
//   delta (kept only when exact), so its chunk points come back bit for bit.
// - EVLR ("lidarscout", kOverviewTableRecord): the tile table, little-endian:
//     "LSOV", u32 version (1), u32 VLR blocks, u32 tiles;
//     per VLR block (the bytes between a tile's header and its point data, shared by alike tiles):
//       u32 size, the bytes;
//     per tile: u16 + the catalog item's id; u64 file size; u16 + validator (file_validator);
//       u64 first point, u32 points (0: none held); i64 x3 delta; u16 + the header's bytes;
//       u32 VLR block; u16 + the bytes after the VLRs that the tile's metadata reads (a LAZ file's
//       chunk-table pointer); u32 + the file's last bytes (its chunk table, EVLRs).
//   A tile's header, VLR block and the bytes after them are its file's first bytes, and with its
//   last bytes they are everything read_tile reads (checked when the sidecar is written), so the
//   tile is read from them (io::File::in_memory) exactly as from its file.
// Opening (dataset.cpp): the catalog's items found in the table (by id) are tiles at once, their chunk
// points the sidecar's; a tile changed since (size or validator) is named and read itself when it is
// read in full (stale_tile_check). Errors are lidarscout::Error naming the sidecar.
#pragma once

#include <array>
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <unordered_map>
#include <vector>

#include "core/thread_pool.hpp"
#include "dataset/dataset.hpp"
#include "dataset/tile.hpp"

namespace lidarscout::io {
class File;
}

namespace lidarscout::dataset {

inline constexpr const char* kOverviewUser = "lidarscout";
inline constexpr std::uint16_t kOverviewTableRecord = 5401;
inline constexpr std::size_t kOverviewTileField = 4;  // bytes of the "tile" field ending each record

// OUT.vpc -> OUT.overview.laz (the extension replaced; appended when there is none).
std::string overview_path_for(const std::string& catalog);

// What `file` is now: its size and, for a local file "mtime NS", for a remote one its ETag or Last-Modified.
FileValidator file_validator(const io::File& file);
// Whether a file that was `made_from` is still so: equal sizes, and equal validators where both are
// of one kind (a sidecar written from local files and served over HTTP compares sizes only).
bool validator_matches(const FileValidator& made_from, const FileValidator& now);

struct OverviewEntry {
    std::string id;  // the catalog item's id
    FileValidator made_from;
    std::vector<std::uint8_t> head;  // the file's bytes [0, head.size()): header, VLRs, chunk-table pointer
    std::vector<std::uint8_t> tail;  // the file's last bytes: chunk table, EVLRs
    std::uint64_t first_point = 0;   // in the sidecar's points
    std::uint32_t points = 0;        // 0: none held
    std::array<std::int64_t, 3> delta{};  // sidecar raw X/Y/Z = the tile's + delta
};

std::vector<std::uint8_t> serialize_overview_table(std::span<const OverviewEntry> entries);
// Throws Error (naming `file`) when the table is malformed. With a `pool`, runs of entries are made on its threads.
std::vector<OverviewEntry> parse_overview_table(std::span<const std::uint8_t> payload, const std::string& file,
                                                ThreadPool* pool = nullptr);

// The decoding of a sidecar's records into its blocks where it goes on after its table was read (a prefetch's: the
// tiles are placed and the dataset opens meanwhile); overview_records waits for its end.
class OverviewDecoding {
public:
    explicit OverviewDecoding(std::string file) : file_(std::move(file)) {}
    // Every record is in.
    void finish();
    // The decoding stopped at `cause`: the records are not used (their tiles' own chunk points are read); one
    // warning (take_stale_tile_warnings) names the sidecar and the cause.
    void fail(const std::string& cause);
    // Nobody reads the records any more: the decoding stopped (no warning).
    void abandon();
    // True once it ended, whether every record is in or not; failed: it ended without them (no wait).
    bool ended() const { return state_.load(std::memory_order_acquire) != kDecoding; }
    bool failed() const { return state_.load(std::memory_order_acquire) == kFailed; }
    // Waits for the end; true when every record is in.
    bool wait() const;

private:
    enum : int { kDecoding, kDone, kFailed };
    void end(int state);

    std::string file_;
    mutable std::mutex mutex_;
    mutable std::condition_variable ended_;
    std::atomic<int> state_{kDecoding};
};

struct OverviewSidecar {
    std::vector<OverviewEntry> entries;
    // Each held tile's chunk points as records of its own format (X/Y/Z its own), entry after entry, in
    // blocks of about kOverviewBlockBytes (an entry in one block, the blocks' entries neighbours on the curve):
    // entry k's records start at record_starts[k] (bytes) of blocks[block_of[k]]. A reader lets a block go
    // once it took every tile's of it (OverviewRelease).
    std::vector<std::shared_ptr<std::vector<std::uint8_t>>> blocks;
    std::vector<std::uint32_t> block_of;
    std::vector<std::size_t> record_starts;
    std::uint16_t record_length = 0;  // of the tiles' records (the sidecar's minus the tile field)
    std::shared_ptr<const OverviewDecoding> decoding;  // where the blocks are still being filled (null: they are)
};

// Reads the sidecar at `path` (a file or URL) in a few large reads and decodes its points; throws Error.
// Takes the prefetch of `path` when one was started (waiting for its table; its Error thrown here): its points
// are then still being decoded (OverviewSidecar::decoding), and an error there leaves them unused.
OverviewSidecar read_overview_sidecar(const std::string& path);

// Starts reading the sidecar at `path` on a thread of its own, at a lower priority, for read_overview_sidecar to
// take: a catalog that names its sidecar before its items (as `lidarscout catalog` writes it) has the country's
// overview fetched while its items are read, and its table read and points decoded once they are
// (decode_overview_prefetch) or once it is taken, whichever comes first: the items' parse has every core (a
// country's, 246 MB, took 1.3 s of CPU on two cores beside the sidecar's 1.1 s). One prefetch is kept: another
// path's replaces it. Nothing when sidecars are not used (use_overview_sidecars).
void prefetch_overview_sidecar(const std::string& path);
// Lets the prefetch go on from its download to its table and points: the catalog that named it is read.
void decode_overview_prefetch();
// Drops a prefetch nobody took (waits for its thread): what open_sources does once it has taken what it uses.
void forget_overview_prefetch();

// The tile an entry places, read from its bytes as from its file at `path`; its TileFile keeps the
// entry's validator and chunk points. Throws Error when the bytes do not make a tile.
Tile tile_from_overview(const OverviewSidecar& sidecar, std::size_t entry, const std::string& path,
                        SharedRecords* shared_records);

// The chunk-point records a sidecar holds for `tile` (record_length each), empty when it holds none
// or not `chunk_points` of them; waits for them where they are still being decoded (empty when that failed).
std::span<const std::uint8_t> overview_records(const Tile& tile, std::uint64_t chunk_points);
// Whether the sidecar holds `chunk_points` records for `tile`, or will once decoded (without waiting).
bool overview_holds(const Tile& tile, std::uint64_t chunk_points);

constexpr std::size_t kOverviewBlockBytes = 1 << 20;

// Lets a sidecar's chunk-point records go block by block as their one reader takes them (the viewer's loader:
// its grid holds them from then on); overview_records is empty for a released block's tiles. No other reader of
// their records may run meanwhile.
class OverviewRelease {
public:
    // `taking`: the tiles whose records the reader will take.
    OverviewRelease(std::span<const DatasetTile> tiles, std::span<const std::uint32_t> taking);
    // The tile's records were taken: its block goes once every tile of it to take was.
    void taken(const Tile& tile);

private:
    static constexpr std::size_t kTrimEvery = 32u << 20;  // bytes released between two trims of the heap
    std::unordered_map<std::vector<std::uint8_t>*, std::size_t> left_;  // per block, its tiles still to take
    std::size_t released_ = 0;  // since the last trim
};

// For a reader about to read `tile` in full from `file`: nullopt when the tile was not placed from a
// sidecar or its file is as the sidecar saw it; else the tile read from the file itself (without an
// overview), and one warning naming it (once per file) kept for take_stale_tile_warnings.
std::optional<Tile> stale_tile_check(const Tile& tile, const io::File& file);

// The tile a reader reads in full from `file`: `tile`, or when stale_tile_check reads it afresh, a copy
// holding the fresh tile, kept in `fresh`.
const DatasetTile& tile_to_read(const DatasetTile& tile, const io::File& file, std::optional<DatasetTile>& fresh);

// The warnings of stale_tile_check since the last call (the CLI shows them when a command ends).
Diagnostics take_stale_tile_warnings();

}  // namespace lidarscout::dataset
