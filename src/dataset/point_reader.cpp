// DecodeUnits (a LAZ tile's units, decoded one by one or in parallel), RecordBatches (a tile cut
// into batches, one batch read or decoded), for_each_record_batch, and RecordPlacer (records to
// points in the dataset's metres).
#include "dataset/point_reader.hpp"
#include "core/point_filter.hpp"

#include <algorithm>
#include <future>
#include <utility>
#include <vector>

#include "core/error.hpp"
#include "core/point_filter.hpp"
#include "core/thread_pool.hpp"
#include "dataset/dataset.hpp"
#include "dataset/las_colour.hpp"
#include "dataset/tile.hpp"
#include "io/file.hpp"
#include "laz/laz.hpp"

namespace lidarscout::dataset {

DecodeUnits::DecodeUnits(const Tile& tile) {
    if (!tile.compressed() || !tile.laz()) throw Error(tile.path(), std::nullopt, "not a LAZ file (internal error)");
    if (!tile.chunks()) throw Error(tile.path(), std::nullopt, "chunk table not read (internal error)");
    layout_ = std::make_unique<laz::LazLayout>(laz::LazLayout{
        tile.header, *tile.laz(), laz::decode_units(tile.header, *tile.laz(), *tile.chunks(), tile.file_size())});
}

DecodeUnits::~DecodeUnits() = default;
DecodeUnits::DecodeUnits(DecodeUnits&&) noexcept = default;

std::size_t DecodeUnits::size() const { return layout_->units.size(); }
std::uint64_t DecodeUnits::first_point(std::size_t u) const { return layout_->units.at(u).first_point; }
std::uint64_t DecodeUnits::point_count(std::size_t u) const { return layout_->units.at(u).point_count; }
std::uint64_t DecodeUnits::byte_offset(std::size_t u) const { return layout_->units.at(u).byte_offset; }
std::uint64_t DecodeUnits::byte_size(std::size_t u) const { return layout_->units.at(u).byte_size; }

void DecodeUnits::decode_bytes(const std::string& path, std::size_t u, std::span<const std::uint8_t> bytes,
                               std::span<std::uint8_t> out, std::uint32_t fields) const {
    laz::decode_unit_bytes(path, *layout_, u, bytes, out, fields);
}

void DecodeUnits::decode(const io::File& file, std::size_t u, std::span<std::uint8_t> out, std::uint32_t fields,
                         std::vector<std::uint8_t>& scratch) const {
    laz::decode_unit(file, *layout_, u, out, fields, scratch);
}

void DecodeUnits::decode(const io::File& file, std::size_t first, std::size_t last, std::span<std::uint8_t> out,
                         std::uint32_t fields, ThreadPool& pool) const {
    laz::decode_units_parallel(file, *layout_, first, last, out, fields, pool);
}

RecordBatches::RecordBatches(const Tile& tile, std::uint64_t batch_points) : tile_(tile) {
    batch_points = std::max<std::uint64_t>(batch_points, 1);
    const std::uint64_t count = tile.header.point_count;
    if (!tile.compressed()) {
        for (std::uint64_t first = 0; first < count; first += batch_points) {
            batches_.push_back({first, std::min(batch_points, count - first)});
        }
        return;
    }
    const DecodeUnits& units = units_.emplace(tile);
    for (std::size_t first = 0; first < units.size();) {
        Batch b{units.first_point(first), 0, first, first};
        while (b.last_unit < units.size() &&
               (b.last_unit == first || b.points + units.point_count(b.last_unit) <= batch_points)) {
            b.points += units.point_count(b.last_unit++);
        }
        batches_.push_back(b);
        first = b.last_unit;
    }
}

RecordBatches::~RecordBatches() = default;
RecordBatches::RecordBatches(RecordBatches&&) noexcept = default;

void RecordBatches::read(const io::File& file, std::size_t k, std::vector<std::uint8_t>& out, std::uint32_t fields,
                         ThreadPool& pool, std::vector<SkippedChunk>* skipped) const {
    const Batch& b = batches_.at(k);
    const auto& h = tile_.header;
    out.resize(b.points * h.record_length);
    if (!units_) {
        file.read_exact(h.offset_to_point_data + b.first_point * h.record_length, out, "point records");
        return;
    }
    try {
        units_->decode(file, b.first_unit, b.last_unit, out, fields, pool);
    } catch (const Error&) {
        if (!skipped) throw;
        read_chunk_by_chunk(file, k, out, fields, pool, *skipped);  // the whole batch again, to find the culprits
    }
}

void RecordBatches::read_chunk_by_chunk(const io::File& file, std::size_t k, std::vector<std::uint8_t>& out,
                                        std::uint32_t fields, ThreadPool& pool,
                                        std::vector<SkippedChunk>& skipped) const {
    const Batch& b = batches_.at(k);
    const std::size_t record = tile_.header.record_length;
    std::size_t kept = 0;  // bytes of `out` holding the records of the chunks decoded so far
    for (std::size_t u = b.first_unit; u < b.last_unit; ++u) {
        const auto span = std::span(out).subspan(kept, units_->point_count(u) * record);
        try {
            units_->decode(file, u, u + 1, span, fields, pool);
            kept += span.size();
        } catch (const Error& e) {
            ErrorRecord error = ErrorRecord::of(e);
            if (!error.offset) error.offset = units_->byte_offset(u);
            skipped.push_back({units_->first_point(u), units_->point_count(u), std::move(error)});
        }
    }
    out.resize(kept);
}

void for_each_record_batch(const io::File& file, const Tile& tile, ThreadPool& pool, const RecordBatchFn& fn,
                           std::uint32_t fields, std::uint64_t batch_points, bool read_ahead,
                           std::vector<SkippedChunk>* skipped) {
    const RecordBatches batches(tile, batch_points);
    std::vector<std::uint8_t> buffers[2];
    const auto read = [&](std::size_t k) { batches.read(file, k, buffers[k % 2], fields, pool, skipped); };
    std::future<void> next;  // declared after the buffers: destroyed (waited for) first
    for (std::size_t k = 0; k < batches.size(); ++k) {
        if (next.valid()) next.get();
        else read(k);
        if (read_ahead && k + 1 < batches.size()) next = std::async(std::launch::async, read, k + 1);
        fn(batches.first_point(k), buffers[k % 2]);
    }
}

RecordPlacer::RecordPlacer(const DatasetTile& tile, bool sixteen_bit, bool rgb)
    : tile_(tile), format_(las::point_format_info(tile.tile.header.point_format)),
      has_rgb_(rgb && format_.rgb_offset >= 0), sixteen_bit_(sixteen_bit) {}

MetricPoint RecordPlacer::attributes(const las::Point& p) const {
    MetricPoint m;
    if (has_rgb_) {
        m.rgb = rgb8_from_las(p.rgb[0], p.rgb[1], p.rgb[2], sixteen_bit_);
        m.coloured = (p.rgb[0] | p.rgb[1] | p.rgb[2]) != 0;
    }
    m.intensity = p.intensity;
    m.classification = p.classification;
    m.return_kinds = returns::kinds_of(p.return_number, p.number_of_returns);
    return m;
}

void RecordPlacer::place(std::span<const std::uint8_t> records, std::size_t first, std::span<MetricPoint> out) const {
    const std::size_t record = tile_.tile.header.record_length, n = out.size();
    std::vector<double> xs(n), ys(n), zs(n);
    for (std::size_t k = 0; k < n; ++k) {
        const auto p = las::decode_point(records.subspan((first + k) * record, record), format_, tile_.tile.header);
        out[k] = attributes(p);
        xs[k] = p.x, ys[k] = p.y, zs[k] = p.z;
    }
    tile_.place(xs, ys, zs);
    for (std::size_t k = 0; k < n; ++k) out[k].x = xs[k], out[k].y = ys[k], out[k].z = zs[k];
}

MetricPoint RecordPlacer::place(const las::Point& point) const {
    MetricPoint m = attributes(point);
    m.x = point.x, m.y = point.y, m.z = point.z;
    tile_.place(m.x, m.y, m.z);
    return m;
}

}  // namespace lidarscout::dataset
