// Batching of record reads/decodes for for_each_record_batch.
#include "dataset/point_reader.hpp"

#include <future>
#include <utility>
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

// Decode units [first, last) of each batch, about batch_points points each.
std::vector<std::pair<std::size_t, std::size_t>> laz_batches(const laz::LazLayout& layout, std::uint64_t batch_points) {
    std::vector<std::pair<std::size_t, std::size_t>> out;
    for (std::size_t first = 0; first < layout.units.size();) {
        std::size_t last = first;
        std::uint64_t points = 0;
        while (last < layout.units.size() &&
               (last == first || points + layout.units[last].point_count <= batch_points)) {
            points += layout.units[last++].point_count;
        }
        out.emplace_back(first, last);
        first = last;
    }
    return out;
}

void decode_laz_batches(const io::File& file, const Tile& tile, ThreadPool& pool, const RecordBatchFn& fn,
                        std::uint32_t fields, std::uint64_t batch_points, bool read_ahead) {
    if (!tile.chunks) throw Error(file.path(), std::nullopt, "chunk table not read (internal error)");
    laz::LazLayout layout{tile.header, *tile.laz,
                          laz::decode_units(tile.header, *tile.laz, *tile.chunks, tile.file_size)};
    const auto batches = laz_batches(layout, batch_points);
    std::vector<std::uint8_t> buffers[2];
    const auto decode = [&](std::size_t k) {
        const auto [first, last] = batches[k];
        std::uint64_t points = 0;
        for (std::size_t u = first; u < last; ++u) points += layout.units[u].point_count;
        std::vector<std::uint8_t>& buf = buffers[k % 2];
        buf.resize(points * tile.header.record_length);
        laz::decode_units_parallel(file, layout, first, last, buf, fields, pool);
    };
    std::future<void> next;  // declared after the buffers: destroyed (waited for) first
    for (std::size_t k = 0; k < batches.size(); ++k) {
        if (next.valid()) next.get();
        else decode(k);
        if (read_ahead && k + 1 < batches.size()) next = std::async(std::launch::async, decode, k + 1);
        fn(layout.units[batches[k].first].first_point, buffers[k % 2]);
    }
}

}  // namespace

void for_each_record_batch(const io::File& file, const Tile& tile, ThreadPool& pool, const RecordBatchFn& fn,
                           std::uint32_t fields, std::uint64_t batch_points, bool read_ahead) {
    batch_points = std::max<std::uint64_t>(batch_points, 1);
    if (tile.compressed()) decode_laz_batches(file, tile, pool, fn, fields, batch_points, read_ahead);
    else read_las_batches(file, tile, fn, batch_points);
}

}  // namespace lidarscout::dataset
