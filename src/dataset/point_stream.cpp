// for_each_metric_batch: records -> points in metres with 8-bit colour.
#include "dataset/point_stream.hpp"

#include <algorithm>
#include <vector>

#include "dataset/chunk_points.hpp"
#include "dataset/dataset.hpp"
#include "dataset/point_reader.hpp"
#include "io/file.hpp"
#include "las/point_format.hpp"

namespace lidarscout::dataset {

bool tile_colour_is_16bit(const Dataset& ds, std::uint32_t tile) {
    const auto& t = ds.tiles.at(tile);
    const auto samples = read_chunk_points(io::File::open(t.tile.path), t.tile, ds.las_stride);
    return colour_is_16bit(samples, [](const ChunkPoint& c) {
        return std::max({c.point.rgb[0], c.point.rgb[1], c.point.rgb[2]});
    });
}

void for_each_metric_batch(const Dataset& ds, std::uint32_t tile, ThreadPool& pool, const MetricBatchFn& fn,
                           std::uint32_t fields) {
    const auto& t = ds.tiles.at(tile);
    const auto file = io::File::open(t.tile.path);
    const auto& fmt = las::point_format_info(t.tile.header.point_format);
    const bool has_rgb = fmt.rgb_offset >= 0 && (fields & laz::fields::kRgb);
    const bool sixteen_bit = has_rgb && tile_colour_is_16bit(ds, tile);
    const std::size_t record = t.tile.header.record_length;
    std::vector<MetricPoint> points;
    std::vector<double> xs, ys, zs;
    for_each_record_batch(file, t.tile, pool, [&](std::uint64_t first, std::span<const std::uint8_t> records) {
        const std::size_t n = records.size() / record;
        points.resize(n);
        xs.resize(n), ys.resize(n), zs.resize(n);
        for (std::size_t k = 0; k < n; ++k) {
            const auto p = las::decode_point(records.subspan(k * record, record), fmt, t.tile.header);
            MetricPoint& m = points[k];
            xs[k] = p.x, ys[k] = p.y, zs[k] = p.z;
            m.rgb = rgb8_from_las(p.rgb[0], p.rgb[1], p.rgb[2], sixteen_bit);
            m.coloured = has_rgb && (p.rgb[0] | p.rgb[1] | p.rgb[2]) != 0;
            m.intensity = p.intensity;
            m.classification = p.classification;
        }
        t.place(xs, ys, zs);
        for (std::size_t k = 0; k < n; ++k) points[k].x = xs[k], points[k].y = ys[k], points[k].z = zs[k];
        fn(first, points);
    }, fields, 1u << 20, true);
}

}  // namespace lidarscout::dataset
