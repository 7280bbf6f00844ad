// Streaming all point records of a tile (LAS or LAZ) in file order, batch by batch: LAZ
// batches are several chunks decoded in parallel, LAS batches are plain reads. Memory stays
// bounded by the batch size, whatever the file size. And the one conversion of a record into a
// point in the dataset's metres with an 8-bit colour (RecordPlacer), which the point stream,
// the chunk-point loader and the viewer all use.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "core/error.hpp"
#include "core/patch_grid.hpp"
#include "las/point_fields.hpp"
#include "las/point_format.hpp"

namespace lidarscout {
class ThreadPool;
}
namespace lidarscout::io {
class File;
}
namespace lidarscout::laz {
struct LazLayout;
}

namespace lidarscout::dataset {

struct Tile;
struct DatasetTile;

// A point in the dataset's frame (metres) with its attributes as the overview keeps them.
struct MetricPoint {
    double x = 0, y = 0, z = 0;  // metres, the dataset's frame
    Rgb8 rgb;                    // 8-bit colour (black when the format has none)
    bool coloured = false;       // the format has colour and this point's is not all zero
    std::uint16_t intensity = 0;
    std::uint8_t classification = 0;
    std::uint8_t return_kinds = 0;  // core/point_filter.hpp returns::kinds_of the point's return and count
};

// LAS records of one tile to MetricPoints: decoded (las::decode_point), placed in the dataset's
// frame (DatasetTile::place: units, reprojection) and coloured at the tile's depth.
class RecordPlacer {
public:
    // `sixteen_bit`: the tile's colour depth (tile_colour_is_16bit, or a decision of the caller's);
    // `rgb` false leaves every point black.
    RecordPlacer(const DatasetTile& tile, bool sixteen_bit, bool rgb = true);

    // Records [first, first + out.size()) of `records` (record_length each) into `out`, placed with
    // one DatasetTile::place call. Throws Error (stage "geo") when a point lies outside the CRSs' area.
    void place(std::span<const std::uint8_t> records, std::size_t first, std::span<MetricPoint> out) const;
    // One point already decoded (a chunk point), placed alone.
    MetricPoint place(const las::Point& point) const;

    const las::PointFormatInfo& format() const { return format_; }

private:
    MetricPoint attributes(const las::Point& p) const;  // all but the position

    const DatasetTile& tile_;
    const las::PointFormatInfo& format_;
    bool has_rgb_, sixteen_bit_;
};

// A LAZ tile's decode units (the chunks of its chunk table, or one unit spanning the point data of
// a compressor-1 file), for readers that decode some of them in an order of their own.
class DecodeUnits {
public:
    // Throws lidarscout::Error when `tile` is not a LAZ tile whose chunk table was read.
    explicit DecodeUnits(const Tile& tile);
    ~DecodeUnits();
    DecodeUnits(DecodeUnits&&) noexcept;

    std::size_t size() const;
    std::uint64_t first_point(std::size_t u) const;  // index in the file of unit u's first point
    std::uint64_t point_count(std::size_t u) const;
    std::uint64_t byte_offset(std::size_t u) const;  // where unit u's compressed bytes start
    std::uint64_t byte_size(std::size_t u) const;    // how many they are
    // Unit u's records into `out` (point_count(u) * record_length bytes), only `fields` (a las::fields
    // mask) decoded; `scratch` keeps the compressed bytes between calls (no allocation once grown).
    // Throws lidarscout::Error (file, chunk) when the unit cannot be decoded.
    void decode(const io::File& file, std::size_t u, std::span<std::uint8_t> out, std::uint32_t fields,
                std::vector<std::uint8_t>& scratch) const;
    // The same from unit u's compressed bytes, read already (a remote file's, fetched with others'); `path`: the
    // file's, for errors.
    void decode_bytes(const std::string& path, std::size_t u, std::span<const std::uint8_t> bytes,
                      std::span<std::uint8_t> out, std::uint32_t fields) const;
    // Units [first, last) decoded in parallel on `pool`, their records back to back in `out`.
    void decode(const io::File& file, std::size_t first, std::size_t last, std::span<std::uint8_t> out,
                std::uint32_t fields, ThreadPool& pool) const;

private:
    std::unique_ptr<laz::LazLayout> layout_;
};

// A LAZ chunk that could not be decoded and was left out of its batch: its points and why.
struct SkippedChunk {
    std::uint64_t first_point = 0, points = 0;
    ErrorRecord error;  // the file, the chunk's byte offset where known, the cause
};

// Called with the index of the batch's first point and its records (record_length each).
using RecordBatchFn = std::function<void(std::uint64_t first_point, std::span<const std::uint8_t> records)>;

// How a tile is cut into batches of about `batch_points` points (at least one whole LAZ chunk),
// and the reading of one batch: for callers that run their own loop, e.g. across tiles.
class RecordBatches {
public:
    // Throws lidarscout::Error when a LAZ tile's chunk table was not read.
    RecordBatches(const Tile& tile, std::uint64_t batch_points);
    ~RecordBatches();
    RecordBatches(RecordBatches&&) noexcept;

    std::size_t size() const { return batches_.size(); }
    // Index in the file of batch k's first point, and its number of points.
    std::uint64_t first_point(std::size_t k) const { return batches_[k].first_point; }
    std::uint64_t point_count(std::size_t k) const { return batches_[k].points; }
    // Batch k's records into `out` (resized); LAZ chunks are decoded in parallel on `pool`.
    // Throws lidarscout::Error when a chunk cannot be decoded, unless `skipped` is given: then
    // each chunk that cannot be is left out of `out` (the records of the others stay in order)
    // and appended to `skipped`.
    void read(const io::File& file, std::size_t k, std::vector<std::uint8_t>& out, std::uint32_t fields,
              ThreadPool& pool, std::vector<SkippedChunk>* skipped = nullptr) const;

private:
    void read_chunk_by_chunk(const io::File& file, std::size_t k, std::vector<std::uint8_t>& out,
                             std::uint32_t fields, ThreadPool& pool, std::vector<SkippedChunk>& skipped) const;
    struct Batch {
        std::uint64_t first_point = 0, points = 0;
        std::size_t first_unit = 0, last_unit = 0;  // LAZ decode units [first, last)
    };
    const Tile& tile_;
    std::optional<DecodeUnits> units_;  // LAZ tiles only
    std::vector<Batch> batches_;
};

// Reads every record of `tile`; `fields` is a las::fields mask (LAS files always give all).
// Batches hold about `batch_points` points (at least one whole LAZ chunk). With `read_ahead`
// the next batch is read or decoded (on `pool`) while fn runs on this one, so fn must not use
// `pool`; memory is then two batches. With `skipped`, a LAZ chunk that cannot be decoded is
// left out and appended to it (RecordBatches::read) instead of ending the read with an Error.
void for_each_record_batch(const io::File& file, const Tile& tile, ThreadPool& pool, const RecordBatchFn& fn,
                           std::uint32_t fields = las::fields::kAll, std::uint64_t batch_points = 1u << 20,
                           bool read_ahead = false, std::vector<SkippedChunk>* skipped = nullptr);

}  // namespace lidarscout::dataset
