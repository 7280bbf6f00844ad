// Point sets: grid cells' chunk points and tiles' decoded points as render batches.
#include "viewer/point_sets.hpp"

#include <algorithm>

#include "dataset/chunk_points.hpp"
#include "dataset/point_reader.hpp"
#include "io/file.hpp"
#include "las/point_format.hpp"
#include "laz/chunk_decoder.hpp"

namespace lidarscout::viewer {
namespace {

constexpr std::size_t kConvertBlock = 16384;  // records converted per pool task

bool tile_colour_is_16bit(const io::File& file, const dataset::DatasetTile& t, std::uint64_t las_stride) {
    const auto samples = dataset::read_chunk_points(file, t.tile, las_stride);
    return dataset::colour_is_16bit(samples, [](const dataset::ChunkPoint& c) {
        return std::max({c.point.rgb[0], c.point.rgb[1], c.point.rgb[2]});
    });
}

// What converting a tile's records needs, fixed per tile.
struct RecordConverter {
    const dataset::DatasetTile* tile;
    const las::PointFormatInfo* format;
    double origin_x, origin_y, origin_z;
    bool sixteen_bit;

    render::PointAttr operator()(std::span<const std::uint8_t> record) const {
        const las::Point p = las::decode_point(record, *format, tile->tile.header);
        const dataset::Rgb8 rgb = dataset::rgb8_from_las(p.rgb[0], p.rgb[1], p.rgb[2], sixteen_bit);
        render::PointAttr a;
        a.dx = static_cast<float>(p.x * tile->xy_to_metres - origin_x);
        a.dy = static_cast<float>(p.y * tile->xy_to_metres - origin_y);
        a.dz = static_cast<float>(p.z * tile->z_to_metres - origin_z);
        a.r = rgb.r, a.g = rgb.g, a.b = rgb.b;
        a.classification = p.classification;
        a.intensity = p.intensity;
        return a;
    }
};

}  // namespace

std::vector<render::PointBatch> batches_of(std::span<const PointSet> sets) {
    std::vector<render::PointBatch> out;
    out.reserve(sets.size());
    for (const auto& s : sets) out.push_back(s.batch());
    return out;
}

std::uint64_t point_count(std::span<const PointSet> sets) {
    std::uint64_t n = 0;
    for (const auto& s : sets) n += s.points.size();
    return n;
}

PointSet cell_point_set(const dataset::PatchGrid& grid, dataset::CellKey cell) {
    PointSet set;
    set.origin_x = grid.cell_min_x(cell);
    set.origin_y = grid.cell_min_y(cell);
    const auto points = grid.points_in(cell);
    set.points.reserve(points.size());
    for (const auto& p : points) {
        render::PointAttr a;
        a.dx = p.dx, a.dy = p.dy, a.dz = p.z;
        a.r = p.rgb.r, a.g = p.rgb.g, a.b = p.rgb.b;
        a.classification = p.classification;
        a.intensity = p.intensity;
        set.points.push_back(a);
    }
    return set;
}

void paint_uncoloured(std::span<PointSet> sets) {
    for (auto& s : sets) {
        for (auto& p : s.points) p.r = p.g = p.b = kUncolouredGrey;
    }
}

std::uint64_t tile_point_set_bytes(const dataset::DatasetTile& tile) {
    return tile.tile.header.point_count * sizeof(render::PointAttr);
}

PointSet tile_point_set(const dataset::DatasetTile& tile, std::uint64_t las_stride, ThreadPool& pool,
                        const std::function<void(std::uint64_t)>& progress) {
    const auto file = io::File::open(tile.tile.path);
    const auto& format = las::point_format_info(tile.tile.header.point_format);
    PointSet set;
    set.origin_x = tile.bounds_m.min_x, set.origin_y = tile.bounds_m.min_y, set.origin_z = tile.bounds_m.min_z;
    const bool sixteen_bit = format.rgb_offset >= 0 && tile_colour_is_16bit(file, tile, las_stride);
    const RecordConverter convert{&tile, &format, set.origin_x, set.origin_y, set.origin_z, sixteen_bit};
    const std::size_t record = tile.tile.header.record_length;
    set.points.reserve(tile.tile.header.point_count);
    const std::uint32_t fields = laz::fields::kXyz | laz::fields::kIntensity | laz::fields::kClassification |
                                 laz::fields::kRgb;
    dataset::for_each_record_batch(
        file, tile.tile, pool,
        [&](std::uint64_t, std::span<const std::uint8_t> records) {
            const std::size_t n = records.size() / record, first = set.points.size();
            set.points.resize(first + n);
            pool.for_each((n + kConvertBlock - 1) / kConvertBlock, [&](std::size_t block) {
                const std::size_t end = std::min(n, (block + 1) * kConvertBlock);
                for (std::size_t k = block * kConvertBlock; k < end; ++k) {
                    set.points[first + k] = convert(records.subspan(k * record, record));
                }
            });
            if (progress) progress(n);
        },
        fields);
    return set;
}

}  // namespace lidarscout::viewer
