// The laz stage's one public header (its facade, as laz-perf's lazperf.hpp): what the other stages
// use to read and write LAZ. Everything else in src/laz (the arithmetic and integer coders, the item
// coders under items/, the point-wise and layered chunk codecs, the encoders) is internal: later
// stages' include views hold only this file (cmake/stages.cmake, FACADE).
//
// Reading: the chunk table (where each independently decodable chunk lies), the decode units of
// a file, and their decoding, one by one or in parallel on the library's thread pool. Writing:
// LasWriter, a LAS or LAZ file from raw point records, renamed into place when finished.
//
// The chunk table: where each chunk of compressed points lies in the file and how many points it
// holds. Chunks are independently decodable, and the first point of each is stored
// raw, so the table is what makes random access (and the chunk-point overview) possible.
//
// Layout (compressors 2 and 3): at offset_to_point_data an int64 gives the table position
// (-1: the position is in the last 8 bytes of the file instead); the first chunk starts right
// after that int64. The table is u32 version (0), u32 chunk count, then per chunk an
// arithmetic-coded point count (only for variable-size chunks) and byte count, each coded
// relative to the previous chunk's.
//
// A dataset holds a table per tile, so it is kept compact: the chunks lie back to back, so their
// byte offsets say where each ends, and when every chunk but the last holds the same number of
// points (fixed-size chunks) that number says where each chunk's points begin: 8 bytes a chunk,
// 16 for variable-size chunks, where 32 would hold each Chunk.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <iterator>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "io/output_file.hpp"
#include "las/header.hpp"
#include "las/laszip_vlr.hpp"
#include "las/point_fields.hpp"
#include "las/vlr.hpp"

namespace lidarscout {
class ThreadPool;
}
namespace lidarscout::io {
class File;
}

namespace lidarscout::laz {

namespace fields = las::fields;  // which fields a decode gives (las/point_fields.hpp)

// ---- the chunk table

struct Chunk {
    std::uint64_t first_point = 0;  // index of the chunk's first point in the file
    std::uint64_t point_count = 0;
    std::uint64_t byte_offset = 0;  // file offset of the chunk's data
    std::uint64_t byte_size = 0;

    bool operator==(const Chunk&) const = default;
};

class ChunkTable {
public:
    std::uint64_t table_offset = 0;      // file offset of the table (0: no table)
    bool offset_from_file_end = false;   // the position came from the file's last 8 bytes

    ChunkTable() = default;
    // `chunks` in file order, back to back (each starts where the one before ends), their points
    // numbered from 0 without a gap; throws lidarscout::Error (an internal error) otherwise.
    explicit ChunkTable(const std::vector<Chunk>& chunks);

    std::size_t size() const { return offsets_.empty() ? 0 : offsets_.size() - 1; }
    bool empty() const { return size() == 0; }
    Chunk operator[](std::size_t i) const;
    Chunk front() const { return (*this)[0]; }
    Chunk back() const { return (*this)[size() - 1]; }
    std::vector<Chunk> chunks() const;  // all of them, in file order
    std::size_t heap_bytes() const;     // what its lists hold

    // The chunks in file order, each made as it is reached.
    class Iterator {
    public:
        using iterator_category = std::input_iterator_tag;
        using value_type = Chunk;
        using difference_type = std::ptrdiff_t;
        using pointer = void;
        using reference = Chunk;

        Iterator(const ChunkTable& table, std::size_t i) : table_(&table), i_(i) {}
        Chunk operator*() const { return (*table_)[i_]; }
        Iterator& operator++() { return ++i_, *this; }
        Iterator operator++(int) { return Iterator(*table_, i_++); }
        bool operator==(const Iterator& o) const { return i_ == o.i_; }

    private:
        const ChunkTable* table_;
        std::size_t i_;
    };
    Iterator begin() const { return {*this, 0}; }
    Iterator end() const { return {*this, size()}; }

private:
    std::vector<std::uint64_t> offsets_;       // where each chunk begins, then where the last ends
    std::vector<std::uint64_t> first_points_;  // each chunk's first point, then the total; empty when regular
    std::uint64_t regular_points_ = 0;         // when regular: the points of every chunk but the last
    std::uint64_t total_points_ = 0;
};

// Whether the table stores a point count per chunk. LASzip treats a chunk size of 0 like the
// "variable" marker 0xFFFFFFFF: its writers then store counts, and its reader expects them.
bool has_variable_chunks(const las::LaszipVlr& laz);

// Reads and validates the chunk table of a LAZ file whose header and LASzip VLR are given.
// A point-wise (compressor 1) or uncompressed file has no table: the result is empty (its
// point data is one stream starting at offset_to_point_data).
//
// Validation (every failure is a lidarscout::Error naming the file, offset and cause):
// - the table position lies between the first chunk and the end of the file; version 0;
// - the chunk count is possible for the bytes between the first chunk and the table (every
//   chunk has at least one byte); it is never used to allocate up front;
// - every chunk has at least one byte and ends at or before the table;
// - the coded entries do not run past the end of the table's bytes (the end of the file, or
//   the EVLRs when they follow the table);
// - point counts: fixed-size chunks hold chunk_size points each but the last, which holds
//   the rest of the header's point count. When the table covers more points than the header
//   announces, the surplus is dropped (chunks past the last point go, the straddling one is
//   shortened), because LASzip's reader stops after the header's count. When it covers
//   fewer, that is an Error: the missing chunks cannot be located without decoding.
ChunkTable read_chunk_table(const io::File& file, const las::Header& header, const las::LaszipVlr& laz);

// ---- decoding a file's points: its decode units (the chunks of the chunk table, or one unit
// spanning the point data of a compressor-1 file), read with positioned reads and decoded in
// parallel. Errors name the file and the chunk.

// What a LAZ file needs for decoding (all read beforehand from its header and VLRs).
struct LazLayout {
    las::Header header;
    las::LaszipVlr laz;
    std::vector<Chunk> units;  // decode units in file order, with first_point set
};

// The decode units: the chunk table's chunks, or for compressor 1 one unit from the point
// data offset to the end of the point data (the EVLRs, else the end of the file).
std::vector<Chunk> decode_units(const las::Header& header, const las::LaszipVlr& laz, const ChunkTable& table,
                                std::uint64_t file_size);

// Decodes unit `index` of `layout` into `out` (unit.point_count * record_length bytes).
// `scratch` holds the compressed bytes between calls (no allocation per chunk once grown).
void decode_unit(const io::File& file, const LazLayout& layout, std::size_t index, std::span<std::uint8_t> out,
                 std::uint32_t fields, std::vector<std::uint8_t>& scratch);
// The same from the unit's compressed bytes, read already (`path`: the file they are of, for errors).
void decode_unit_bytes(const std::string& path, const LazLayout& layout, std::size_t index,
                       std::span<const std::uint8_t> bytes, std::span<std::uint8_t> out, std::uint32_t fields);

// Decodes the units [first, last) in parallel into `out` (their records back to back).
void decode_units_parallel(const io::File& file, const LazLayout& layout, std::size_t first, std::size_t last,
                           std::span<std::uint8_t> out, std::uint32_t fields, ThreadPool& pool);

// ---- writing a LAS or LAZ file: the header, the VLRs (plus the LASzip VLR for LAZ), the records
// streamed in (for LAZ cut into chunks encoded in parallel, then the chunk table), the EVLRs and
// the final header. The file appears under its name only when finish() completes
// (io::AtomicOutputFile).

struct LasWriterOptions {
    bool compress = true;               // write LAZ (else LAS)
    std::uint32_t chunk_size = 50'000;  // points per LAZ chunk
    bool variable_chunks = false;       // store per-chunk point counts (as COPC does)
};

struct LasWriterResult {
    std::uint64_t points = 0;
    std::uint64_t chunks = 0;  // 0 for LAS
    std::uint64_t bytes_written = 0;
};

class LasWriter {
public:
    // Starts `path` (refused when it names the file `protect`, an input). `header` gives the
    // version, header_size (the standard size plus `header_trailing` user bytes), point
    // format, record length, scale/offset and the descriptive fields; the writer sets the
    // structural ones (compression bit, VLR/EVLR counts and offsets, point count). A LASzip
    // VLR in `vlrs` is dropped: the writer adds its own for LAZ. Throws lidarscout::Error.
    LasWriter(const std::string& path, las::Header header, std::vector<las::Vlr> vlrs, const LasWriterOptions& options,
              ThreadPool& pool, std::vector<std::uint8_t> header_trailing = {}, const std::string& protect = {});
    ~LasWriter();  // without finish() the partial output is removed
    LasWriter(const LasWriter&) = delete;
    LasWriter& operator=(const LasWriter&) = delete;

    // Appends whole records (record_length bytes each) in file order.
    void add(std::span<const std::uint8_t> records);
    std::uint64_t points() const noexcept { return points_; }

    // The header written at finish(): callers may update descriptive fields (bounds, points
    // by return, GPS time range) until then.
    las::Header& header() noexcept { return header_; }

    // Writes the remaining chunks, the chunk table, `evlrs` (payloads in Vlr::data) and the
    // final header (point count = records added), then renames the file into place.
    LasWriterResult finish(const std::vector<las::Vlr>& evlrs = {});

private:
    class Chunks;  // the LAZ chunk cutter and encoder

    las::Header header_;
    std::vector<std::uint8_t> header_trailing_;
    std::vector<las::Vlr> vlrs_;
    LasWriterOptions options_;
    io::AtomicOutputFile out_;
    las::LaszipVlr laz_;
    std::unique_ptr<Chunks> chunks_;  // set for LAZ
    std::uint64_t points_ = 0;
    std::uint64_t table_pointer_at_ = 0;
    bool finished_ = false;
};

}  // namespace lidarscout::laz
