// clip_to_file: the touched tiles checked alike, the output's header from the first, the kept
// records streamed into a LasWriter, bounds and return counts set at the end.
#include "pipelines/clip.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "core/thread_pool.hpp"
#include "io/file.hpp"
#include "laz/laz.hpp"
#include "pipelines/tile_writer.hpp"

namespace lidarscout::pipelines {
namespace {

Error clip_error(const std::string& cause) { return Error::in_stage("clip", cause); }

std::string tile_name(const dataset::Dataset& ds, std::uint32_t t) { return io::display_path(ds.tiles[t].tile.path()); }

// The touched tiles must share a point format and record length, and be in the frame's CRS.
void check_tiles_alike(const dataset::Dataset& ds, std::span<const std::uint32_t> tiles) {
    const auto& first = ds.tiles[tiles[0]].tile.header;
    for (const auto t : tiles) {
        const auto& h = ds.tiles[t].tile.header;
        if (h.point_format != first.point_format || h.record_length != first.record_length) {
            throw clip_error(fmt::format("the area touches tiles of different point formats: {} (format {}, {} bytes a "
                                         "record) and {} (format {}, {} bytes); convert them to one format first",
                                         tile_name(ds, tiles[0]), first.point_format, first.record_length,
                                         tile_name(ds, t), h.point_format, h.record_length));
        }
        if (ds.tiles[t].to_frame) {
            throw clip_error(fmt::format("{} is not in the dataset's CRS ({}): clip does not reproject raw "
                                         "coordinates; clip its tiles apart or choose their CRS with --crs",
                                         tile_name(ds, t), ds.frame.crs.empty() ? "unknown" : ds.frame.crs));
        }
    }
}

// The header of the output: the first tile's, its structural fields left to the writer.
las::Header output_header(const las::Header& first) {
    las::Header h = first;
    h.header_size = las::minimum_header_size(h.version_major, h.version_minor);  // user bytes not kept
    h.min = {INFINITY, INFINITY, INFINITY};
    h.max = {-INFINITY, -INFINITY, -INFINITY};
    h.points_by_return = {};
    h.legacy_points_by_return = {};
    return h;
}

// Writes kept batches: records copied, or their X/Y/Z re-quantized to the output's scale/offset.
class ClipSink {
public:
    ClipSink(laz::LasWriter& writer, const dataset::Dataset& ds) : writer_(writer), ds_(ds) {}

    void add(const RegionBatch& b) {
        const auto& h = ds_.tiles[b.tile].tile.header;
        auto& out = writer_.header();
        if (h.scale == out.scale && h.offset == out.offset) {
            writer_.add(b.records);
        } else {
            requantized_.assign(b.records.begin(), b.records.end());
            for (std::size_t i = 0; i < b.points.size(); ++i) requantize(b.points[i].point, i * h.record_length);
            writer_.add(requantized_);
        }
        for (const auto& p : b.points) count(p.point);
    }

private:
    void requantize(const las::Point& p, std::size_t at) {
        const auto& out = writer_.header();
        const double v[3] = {p.x, p.y, p.z};
        for (int k = 0; k < 3; ++k) {
            const double q = std::round((v[k] - out.offset[k]) / out.scale[k]);
            if (!(std::abs(q) <= std::numeric_limits<std::int32_t>::max())) {
                throw clip_error("a point's coordinate does not fit the output's scale and offset (those of its "
                                 "first tile)");
            }
            const auto raw = static_cast<std::int32_t>(q);
            std::memcpy(requantized_.data() + at + 4 * k, &raw, 4);
        }
    }

    void count(const las::Point& p) {
        auto& h = writer_.header();
        const double v[3] = {p.x, p.y, p.z};
        for (int k = 0; k < 3; ++k) h.min[k] = std::min(h.min[k], v[k]), h.max[k] = std::max(h.max[k], v[k]);
        const int r = std::clamp<int>(p.return_number, 1, 15);
        ++h.points_by_return[r - 1];
        if (r <= 5) ++h.legacy_points_by_return[r - 1];
    }

    laz::LasWriter& writer_;
    const dataset::Dataset& ds_;
    std::vector<std::uint8_t> requantized_;
};

// Loaded EVLRs of the first tile; the others are named in notes.
std::vector<las::Vlr> kept_evlrs(const dataset::Tile& tile, std::vector<std::string>& notes) {
    std::vector<las::Vlr> out;
    for (const auto& v : tile.evlrs()) {
        if (v.data_loaded) out.push_back(v);
        else notes.push_back(fmt::format("EVLR {} {} ({} bytes) not copied", v.user_id, v.record_id, v.data_size));
    }
    return out;
}

}  // namespace

ClipResult clip_to_file(const dataset::Dataset& ds, const ClipRequest& request, ThreadPool& pool) {
    const auto& box = request.region.box;
    const std::vector<std::uint32_t> tiles = tiles_touching(ds, request.region);
    if (tiles.empty()) {
        const auto& b = ds.bounds_m;
        const double f = ds.frame.xy_to_metres;
        throw clip_error(fmt::format("no tile touches the area ({:.3f}, {:.3f}) - ({:.3f}, {:.3f}); the dataset covers "
                                     "({:.3f}, {:.3f}) - ({:.3f}, {:.3f}) in its CRS's units",
                                     box.min_x, box.min_y, box.max_x, box.max_y, b.min_x / f, b.min_y / f,
                                     b.max_x / f, b.max_y / f));
    }
    check_tiles_alike(ds, tiles);
    ClipResult result;
    const auto& first = ds.tiles[tiles[0]].tile;
    const std::vector<las::Vlr> evlrs = kept_evlrs(first, result.notes);
    laz::LasWriterOptions options;
    options.compress = wants_laz(request.output);
    laz::LasWriter writer(request.output, output_header(first.header), first.vlrs(), options, pool);
    ClipSink sink(writer, ds);
    result.read = read_region_points(ds, tiles, request.region, request.filter, pool,
                                     [&](const RegionBatch& b) { sink.add(b); }, request.watch);
    if (result.read.cancelled) throw clip_error("cancelled");  // the writer removes its temporary file
    if (writer.points() == 0) writer.header().min = writer.header().max = {0, 0, 0};
    const laz::LasWriterResult written = writer.finish(evlrs);
    result.points_written = written.points;
    result.bytes_written = written.bytes_written;
    return result;
}

}  // namespace lidarscout::pipelines
