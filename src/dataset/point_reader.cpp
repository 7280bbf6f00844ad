// Batching of record reads/decodes for for_each_record_batch.
#include "dataset/point_reader.hpp"

#include <vector>

#include "core/error.hpp"
#include "core/thread_pool.hpp"
#include "dataset/tile.hpp"
#include "io/file.hpp"
#include "laz/file_decoder.hpp"

namespace lidarscout::dataset {
namespace {

void read_las_batches(const io::File& file, const Tile& tile, const RecordBatchFn& fn, std::uint64_t batch_points) {
    const auto& h = tile.header;
    std::vector<std::uint8_t> buf;
    for (std::uint64_t first = 0; first < h.point_count; first += batch_points) {
        const std::uint64_t n = std::min(batch_points, h.point_count - first);
        buf.resize(n * h.record_length);
        file.read_exact(h.offset_to_point_data + first * h.record_length, buf, "point records");
        fn(first, buf);
    }
}

void decode_laz_batches(const io::File& file, const Tile& tile, ThreadPool& pool, const RecordBatchFn& fn,
                        std::uint32_t fields, std::uint64_t batch_points) {
    if (!tile.chunks) throw Error(file.path(), std::nullopt, "chunk table not read (internal error)");
    laz::LazLayout layout{tile.header, *tile.laz, laz::decode_units(tile.header, *tile.laz, *tile.chunks, tile.file_size)};
    std::vector<std::uint8_t> buf;
    for (std::size_t first = 0; first < layout.units.size();) {
        std::size_t last = first;
        std::uint64_t points = 0;
        while (last < layout.units.size() && (last == first || points + layout.units[last].point_count <= batch_points)) {
            points += layout.units[last++].point_count;
        }
        buf.resize(points * tile.header.record_length);
        laz::decode_units_parallel(file, layout, first, last, buf, fields, pool);
        fn(layout.units[first].first_point, buf);
        first = last;
    }
}

}  // namespace

void for_each_record_batch(const io::File& file, const Tile& tile, ThreadPool& pool, const RecordBatchFn& fn,
                           std::uint32_t fields, std::uint64_t batch_points) {
    batch_points = std::max<std::uint64_t>(batch_points, 1);
    if (tile.compressed()) decode_laz_batches(file, tile, pool, fn, fields, batch_points);
    else read_las_batches(file, tile, fn, batch_points);
}

}  // namespace lidarscout::dataset
