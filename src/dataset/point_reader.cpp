// RecordBatches (a tile cut into batches, one batch read or decoded) and for_each_record_batch.
#include "dataset/point_reader.hpp"

#include <algorithm>
#include <future>
#include <utility>
#include <vector>

#include "core/error.hpp"
#include "core/thread_pool.hpp"
#include "dataset/tile.hpp"
#include "io/file.hpp"
#include "laz/file_decoder.hpp"

namespace lidarscout::dataset {

RecordBatches::RecordBatches(const Tile& tile, std::uint64_t batch_points) : tile_(tile) {
    batch_points = std::max<std::uint64_t>(batch_points, 1);
    const std::uint64_t count = tile.header.point_count;
    if (!tile.compressed()) {
        for (std::uint64_t first = 0; first < count; first += batch_points) {
            batches_.push_back({first, std::min(batch_points, count - first)});
        }
        return;
    }
    if (!tile.chunks()) throw Error(tile.path(), std::nullopt, "chunk table not read (internal error)");
    layout_ = std::make_unique<laz::LazLayout>(laz::LazLayout{
        tile.header, *tile.laz(), laz::decode_units(tile.header, *tile.laz(), *tile.chunks(), tile.file_size())});
    const auto& units = layout_->units;
    for (std::size_t first = 0; first < units.size();) {
        Batch b{units[first].first_point, 0, first, first};
        while (b.last_unit < units.size() &&
               (b.last_unit == first || b.points + units[b.last_unit].point_count <= batch_points)) {
            b.points += units[b.last_unit++].point_count;
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
    if (!layout_) {
        file.read_exact(h.offset_to_point_data + b.first_point * h.record_length, out, "point records");
        return;
    }
    try {
        laz::decode_units_parallel(file, *layout_, b.first_unit, b.last_unit, out, fields, pool);
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
        const laz::Chunk& c = layout_->units[u];
        const auto span = std::span(out).subspan(kept, c.point_count * record);
        try {
            laz::decode_units_parallel(file, *layout_, u, u + 1, span, fields, pool);
            kept += span.size();
        } catch (const Error& e) {
            ErrorRecord error = ErrorRecord::of(e);
            if (!error.offset) error.offset = c.byte_offset;
            skipped.push_back({c.first_point, c.point_count, std::move(error)});
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

}  // namespace lidarscout::dataset
