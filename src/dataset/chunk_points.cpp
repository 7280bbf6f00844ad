// Reading chunk points: one small positioned read per point, no decompression.
#include "dataset/chunk_points.hpp"

#include <algorithm>

#include "core/error.hpp"
#include "dataset/tile.hpp"
#include "io/file.hpp"
#include "laz/file_decoder.hpp"

namespace lidarscout::dataset {
namespace {

ChunkPoint read_one(const io::File& file, const Tile& tile, std::uint64_t index, std::uint64_t offset,
                    std::vector<std::uint8_t>& buf) {
    file.read_exact(offset, buf, "chunk point record");
    const auto& fmt = las::point_format_info(tile.header.point_format);
    return {index, las::decode_point(buf, fmt, tile.header)};
}

}  // namespace

std::vector<ChunkPoint> read_chunk_points(const io::File& file, const Tile& tile, std::uint64_t las_stride) {
    std::vector<ChunkPoint> out;
    std::vector<std::uint8_t> buf(tile.header.record_length);
    if (tile.compressed()) {
        if (!tile.chunks) throw Error(file.path(), std::nullopt, "chunk table not read (internal error)");
        const auto units = laz::decode_units(tile.header, *tile.laz, *tile.chunks, tile.file_size);
        out.reserve(units.size());
        for (const auto& c : units) {
            if (c.point_count == 0) continue;
            out.push_back(read_one(file, tile, c.first_point, c.byte_offset, buf));
        }
        return out;
    }
    if (las_stride == 0) throw Error("chunk point stride must be positive");
    const auto& h = tile.header;
    out.reserve(h.point_count / las_stride + 1);
    for (std::uint64_t i = 0; i < h.point_count; i += las_stride) {
        out.push_back(read_one(file, tile, i, h.offset_to_point_data + i * h.record_length, buf));
    }
    return out;
}

}  // namespace lidarscout::dataset

namespace lidarscout::dataset {

std::uint64_t chunk_point_count(const Tile& tile, std::uint64_t las_stride) {
    if (tile.compressed()) {
        if (!tile.chunks) return 0;
        const auto units = laz::decode_units(tile.header, *tile.laz, *tile.chunks, tile.file_size);
        return static_cast<std::uint64_t>(
            std::count_if(units.begin(), units.end(), [](const auto& c) { return c.point_count > 0; }));
    }
    return (tile.header.point_count + las_stride - 1) / las_stride;
}

}  // namespace lidarscout::dataset
