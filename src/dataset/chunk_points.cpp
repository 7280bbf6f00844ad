// Reading chunk points: one small positioned read per point, no decompression.
#include "dataset/chunk_points.hpp"

#include "core/error.hpp"
#include "dataset/overview_sidecar.hpp"
#include "dataset/tile.hpp"
#include "io/file.hpp"
#include "laz/laz.hpp"

namespace lidarscout::dataset {

std::vector<ChunkPointLocation> chunk_point_locations(const Tile& tile, std::uint64_t las_stride) {
    std::vector<ChunkPointLocation> out;
    if (tile.compressed()) {
        if (!tile.chunks()) throw Error(tile.path(), std::nullopt, "chunk table not read (internal error)");
        const auto units = laz::decode_units(tile.header, *tile.laz(), *tile.chunks(), tile.file_size());
        out.reserve(units.size());
        for (const auto& c : units) {
            if (c.point_count > 0) out.push_back({c.first_point, c.byte_offset});
        }
        return out;
    }
    if (las_stride == 0) throw Error("chunk point stride must be positive");
    const auto& h = tile.header;
    out.reserve(h.point_count / las_stride + 1);
    for (std::uint64_t i = 0; i < h.point_count; i += las_stride) {
        out.push_back({i, h.offset_to_point_data + i * h.record_length});
    }
    return out;
}

std::vector<ChunkPoint> read_chunk_points(const io::File& file, const Tile& tile, std::uint64_t las_stride) {
    const auto locations = chunk_point_locations(tile, las_stride);
    std::vector<std::pair<std::uint64_t, std::uint64_t>> ranges;  // (read together: a remote tile's in one request)
    ranges.reserve(locations.size());
    for (const auto& at : locations) ranges.emplace_back(at.offset, tile.header.record_length);
    const auto records = file.read_ranges(ranges, "chunk point record");
    const auto& fmt = las::point_format_info(tile.header.point_format);
    std::vector<ChunkPoint> out;
    out.reserve(locations.size());
    for (std::size_t k = 0; k < locations.size(); ++k) {
        out.push_back({locations[k].index, las::decode_point(records[k], fmt, tile.header)});
    }
    return out;
}

std::vector<ChunkPoint> tile_chunk_points(const Tile& tile, std::uint64_t las_stride) {
    const auto locations = chunk_point_locations(tile, las_stride);
    const auto records = overview_records(tile, locations.size());
    if (records.empty()) return read_chunk_points(io::File::open(tile.path()), tile, las_stride);
    const std::size_t length = tile.header.record_length;
    const auto& fmt = las::point_format_info(tile.header.point_format);
    std::vector<ChunkPoint> out;
    out.reserve(locations.size());
    for (std::size_t k = 0; k < locations.size(); ++k) {
        out.push_back({locations[k].index, las::decode_point(records.subspan(k * length, length), fmt, tile.header)});
    }
    return out;
}

std::uint64_t chunk_point_count(const Tile& tile, std::uint64_t las_stride) {
    if (tile.compressed() && !tile.chunks()) return 0;
    if (!tile.compressed() && las_stride > 0) return (tile.header.point_count + las_stride - 1) / las_stride;
    return chunk_point_locations(tile, las_stride).size();
}

}  // namespace lidarscout::dataset
