// read_overview: each tile's chunk points read on a pool into its own span of the table, the spans of
// tiles that failed or held fewer points closed up at the end.
#include "python/overview.hpp"

#include <algorithm>
#include <optional>
#include <thread>

#include "core/thread_pool.hpp"
#include "dataset/chunk_points.hpp"
#include "pipelines/region_points.hpp"

namespace lidarscout::python {
namespace {

// Writes tile `t`'s chunk points at `out` (room for `room`); returns how many were written.
std::size_t read_tile_points(const dataset::Dataset& ds, std::uint32_t t, PointRecord* out, std::size_t room) {
    const auto& tile = ds.tiles[t];
    const auto points = dataset::tile_chunk_points(tile.tile, ds.las_stride);
    const pipelines::FrameUnits units(tile, ds.frame);
    const std::size_t n = std::min(points.size(), room);
    for (std::size_t i = 0; i < n; ++i) {
        double x, y, z;
        units(points[i].point, x, y, z);
        out[i] = point_record(points[i].point, x, y, z, t);
    }
    return n;
}

}  // namespace

Overview read_overview(const dataset::Dataset& ds, unsigned threads) {
    std::vector<std::size_t> first(ds.tiles.size() + 1, 0);
    for (std::size_t t = 0; t < ds.tiles.size(); ++t) {
        first[t + 1] = first[t] + dataset::chunk_point_count(ds.tiles[t].tile, ds.las_stride);
    }
    Overview o{PointTable(first.back()), {}};
    std::vector<std::size_t> written(ds.tiles.size(), 0);
    std::vector<std::optional<ErrorRecord>> failed(ds.tiles.size());
    ThreadPool pool(threads ? threads : std::max(1u, std::thread::hardware_concurrency()));
    pool.for_each(ds.tiles.size(), [&](std::size_t t) {
        try {
            written[t] = read_tile_points(ds, static_cast<std::uint32_t>(t), o.points.data() + first[t],
                                          first[t + 1] - first[t]);
        } catch (const Error& e) {
            failed[t] = ErrorRecord::of(e.file().empty() ? e.with_file(ds.tiles[t].tile.path()) : e);
        }
    });
    o.points.grow(first.back());
    for (std::size_t t = ds.tiles.size(); t-- > 0;) {  // from the end, so that each gap moves the fewest records
        const std::size_t room = first[t + 1] - first[t];
        if (written[t] < room) o.points.erase(first[t] + written[t], room - written[t]);
        if (failed[t]) o.skipped.push_back(*failed[t]);
    }
    std::reverse(o.skipped.begin(), o.skipped.end());
    return o;
}

}  // namespace lidarscout::python
