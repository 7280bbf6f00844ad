// clip_to_file: the touched tiles checked alike and for waveform data, the output's header from the
// first (its CRS and scale/offset the frame's when a touched tile is reprojected), the kept records
// streamed into a LasWriter, bounds, return counts and GPS time range set at the end.
#include "pipelines/clip.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>

#include "core/thread_pool.hpp"
#include "io/file.hpp"
#include "las/header_writer.hpp"
#include "laz/laz.hpp"
#include "pipelines/output_records.hpp"
#include "pipelines/tile_writer.hpp"

namespace lidarscout::pipelines {
namespace {

Error clip_error(const std::string& cause) { return Error::in_stage("clip", cause); }

std::string tile_name(const dataset::Dataset& ds, std::uint32_t t) { return io::display_path(ds.tiles[t].tile.path()); }

// The touched tiles must share a point format and record length.
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
    }
}

// Global encoding bits of LAS 1.3+: where the waveform data packets are.
constexpr std::uint16_t kWaveformInternal = 1u << 1;
constexpr std::uint16_t kWaveformExternal = 1u << 2;

bool is_waveform_record(const las::Vlr& v) { return v.extended && v.record_id == 65535; }

// A tile's waveform data in words ("" when it has none, or its format has no wave packets).
std::string waveform_data(const dataset::Tile& tile) {
    const auto& h = tile.header;
    if (las::point_format_info(h.point_format).wave_offset < 0) return "";
    if (h.global_encoding & kWaveformExternal) {
        const std::string path = io::display_path(tile.path());
        const auto dot = path.rfind('.');
        return "waveform data packets in an external file (" + path.substr(0, dot) + ".wdp)";
    }
    const bool record = std::any_of(tile.evlrs().begin(), tile.evlrs().end(), is_waveform_record);
    if ((h.global_encoding & kWaveformInternal) || h.waveform_offset != 0 || record) {
        return fmt::format("waveform data packets inside the file (from byte {})", h.waveform_offset);
    }
    return "";
}

// Whether the kept records' wave packets must be cleared: when a touched tile has waveform data, which a
// clip cannot carry (its packets address it in that tile). Refused (nothing written yet) unless forced;
// forced, a note names what is dropped.
bool drop_waveforms(const dataset::Dataset& ds, std::span<const std::uint32_t> tiles, const ClipRequest& request,
                    std::vector<std::string>& notes) {
    std::size_t with_data = 0;
    std::string first;
    for (const auto t : tiles) {
        const std::string what = waveform_data(ds.tiles[t].tile);
        if (what.empty()) continue;
        if (!request.force) {
            throw Error(tile_name(ds, t), std::nullopt,
                        fmt::format("{}: {} cannot carry them into {} (its points' wave packets address them there); "
                                    "nothing written (--force writes its points' wave packets without waveform "
                                    "data: descriptor index, offset and size 0)",
                                    what, request.command, io::display_path(request.output)));
        }
        if (with_data++ == 0) first = tile_name(ds, t) + ": " + what;
    }
    if (with_data == 0) return false;
    notes.push_back(fmt::format("waveform data dropped ({} of the {} tiles touched have it; {}): the wave packets "
                                "written have descriptor index, offset and size 0",
                                with_data, tiles.size(), first));
    return true;
}

// Whether a tile's coordinates as stored are the frame's: its CRS (not reprojected) and units.
bool stored_in_frame(const dataset::DatasetTile& t, const dataset::Frame& frame) {
    return !t.to_frame && t.xy_to_metres == frame.xy_to_metres && t.z_to_metres == frame.z_to_metres;
}

std::size_t reprojected_count(const dataset::Dataset& ds, std::span<const std::uint32_t> tiles) {
    return static_cast<std::size_t>(std::count_if(tiles.begin(), tiles.end(), [&](std::uint32_t t) {
        return ds.tiles[t].to_frame != nullptr;
    }));
}

// A power of ten at most `s` (0.001 for 0.0025).
double power_of_ten_at_most(double s) { return std::pow(10.0, std::floor(std::log10(s) + 1e-9)); }

// Metres per x/y unit, a degree taken as a degree of latitude (111,320 m; a degree of longitude is
// shorter, so a scale from it is finer than needed there).
double metres_per_unit(double xy_to_metres, bool degrees) { return degrees ? 111'320.0 : xy_to_metres; }

// The output's scale and offset when it is written in the frame's CRS: those of the first touched tile
// stored in the frame, else, per axis, a power of ten no coarser than any touched tile's scale in the
// frame's units (for degrees, no finer than 1e-7, about 1 cm) and an x/y offset rounded to 1000 units
// (1 degree) near the middle of the touched tiles' bounds within the area (z offset 0).
void frame_scale_offset(las::Header& out, const dataset::Dataset& ds, std::span<const std::uint32_t> tiles,
                        const Region& region) {
    for (const auto t : tiles) {
        if (!stored_in_frame(ds.tiles[t], ds.frame)) continue;
        out.scale = ds.tiles[t].tile.header.scale;
        out.offset = ds.tiles[t].tile.header.offset;
        return;
    }
    const double f = ds.frame.xy_to_metres, fz = ds.frame.z_to_metres;
    const double frame_m = metres_per_unit(f, ds.frame.geographic);
    std::array<double, 3> finest{INFINITY, INFINITY, INFINITY};
    dataset::Bounds b;
    for (const auto t : tiles) {
        const auto& dt = ds.tiles[t];
        const auto& s = dt.tile.header.scale;
        const double tile_m = metres_per_unit(dt.xy_to_metres, dt.tile.crs().geographic);
        finest[0] = std::min(finest[0], s[0] * tile_m / frame_m);
        finest[1] = std::min(finest[1], s[1] * tile_m / frame_m);
        finest[2] = std::min(finest[2], s[2] * dt.z_to_metres / fz);
        b.extend(dt.bounds_m);
    }
    if (ds.frame.geographic) finest[0] = std::max(finest[0], 1e-7), finest[1] = std::max(finest[1], 1e-7);
    const auto middle = [](double lo, double hi, double area_lo, double area_hi) {
        return 0.5 * (std::max(lo, area_lo) + std::min(hi, area_hi));
    };
    const auto& a = region.box;
    const double mx = middle(b.min_x / f, b.max_x / f, a.min_x, a.max_x);
    const double my = middle(b.min_y / f, b.max_y / f, a.min_y, a.max_y);
    for (int k = 0; k < 3; ++k) out.scale[k] = power_of_ten_at_most(finest[k]);
    const double step = ds.frame.geographic ? 1.0 : 1000.0;
    out.offset = {std::round(mx / step) * step, std::round(my / step) * step, 0.0};
}

// The header of the output: the first tile's, its structural fields left to the writer, the standard
// size of its version (user bytes not kept), no waveform data (never carried), the ranges to be set.
las::Header output_header(const las::Header& first) {
    las::Header h = first;
    h.header_size = las::standard_header_size(h.version_major, h.version_minor);
    h.global_encoding &= static_cast<std::uint16_t>(~(kWaveformInternal | kWaveformExternal));
    h.waveform_offset = 0;
    h.min = {INFINITY, INFINITY, INFINITY};
    h.max = {-INFINITY, -INFINITY, -INFINITY};
    h.points_by_return = {};
    h.legacy_points_by_return = {};
    const bool gps = las::point_format_info(h.point_format).gps_offset >= 0;
    h.min_gps_time = gps ? INFINITY : 0.0;
    h.max_gps_time = gps ? -INFINITY : 0.0;
    return h;
}

// Writes kept batches: records copied, or their X/Y/Z re-quantized to the output's scale/offset, from
// their coordinates as stored or, for an output in the frame's CRS, from where they lie in the frame;
// with `drop_waveforms`, their wave packets cleared of the waveform data they address.
class ClipSink {
public:
    ClipSink(laz::LasWriter& writer, const dataset::Dataset& ds, bool in_frame, bool drop_waveforms)
        : writer_(writer), ds_(ds), in_frame_(in_frame),
          wave_offset_(drop_waveforms ? las::point_format_info(writer.header().point_format).wave_offset : -1) {}

    void add(const RegionBatch& b) {
        const auto& t = ds_.tiles[b.tile];
        const auto& h = t.tile.header;
        const auto& out = writer_.header();
        const bool as_stored = !in_frame_ || stored_in_frame(t, ds_.frame);
        const bool same_quantization = as_stored && h.scale == out.scale && h.offset == out.offset;
        if (same_quantization && wave_offset_ < 0) {
            writer_.add(b.records);
            for (const auto& p : b.points) count({p.point.x, p.point.y, p.point.z}, p.point);
            return;
        }
        requantized_.assign(b.records.begin(), b.records.end());
        for (std::size_t i = 0; i < b.points.size(); ++i) {
            const auto& p = b.points[i];
            const std::size_t at = i * h.record_length;
            if (wave_offset_ >= 0) clear_waveform_reference(at + static_cast<std::size_t>(wave_offset_));
            if (same_quantization) {
                count({p.point.x, p.point.y, p.point.z}, p.point);
                continue;
            }
            const std::array<double, 3> v = in_frame_ ? std::array{p.x, p.y, p.z}
                                                      : std::array{p.point.x, p.point.y, p.point.z};
            count(requantize(v, at), p.point);
        }
        writer_.add(requantized_);
    }

private:
    // Writes the raw X/Y/Z of `v` at `at`; returns the coordinates they stand for.
    std::array<double, 3> requantize(const std::array<double, 3>& v, std::size_t at) {
        const auto& out = writer_.header();
        std::array<double, 3> stored{};
        for (int k = 0; k < 3; ++k) {
            const double q = std::round((v[k] - out.offset[k]) / out.scale[k]);
            if (!(std::abs(q) <= std::numeric_limits<std::int32_t>::max())) {
                throw clip_error("a point's coordinate does not fit the output's scale and offset");
            }
            const auto raw = static_cast<std::int32_t>(q);
            std::memcpy(requantized_.data() + at + 4 * k, &raw, 4);
            stored[k] = raw * out.scale[k] + out.offset[k];
        }
        return stored;
    }

    // The wave packet at `at`: descriptor index 0 ("no waveform data"), data offset and size 0.
    void clear_waveform_reference(std::size_t at) { std::memset(requantized_.data() + at, 0, 1 + 8 + 4); }

    void count(const std::array<double, 3>& v, const las::Point& p) {
        auto& h = writer_.header();
        for (int k = 0; k < 3; ++k) h.min[k] = std::min(h.min[k], v[k]), h.max[k] = std::max(h.max[k], v[k]);
        const int r = std::clamp<int>(p.return_number, 1, 15);
        ++h.points_by_return[r - 1];
        if (r <= 5) ++h.legacy_points_by_return[r - 1];
        if (!gps_) return;
        h.min_gps_time = std::min(h.min_gps_time, p.gps_time);
        h.max_gps_time = std::max(h.max_gps_time, p.gps_time);
    }

    laz::LasWriter& writer_;
    const dataset::Dataset& ds_;
    bool in_frame_;
    int wave_offset_;  // of the wave packet in a record, when dropping waveform data; else -1
    bool gps_ = las::point_format_info(writer_.header().point_format).gps_offset >= 0;
    std::vector<std::uint8_t> requantized_;
};

// The VLRs of the first tile but its COPC info (the output is no COPC file).
std::vector<las::Vlr> kept_vlrs(const dataset::Tile& tile, std::vector<std::string>& notes) {
    std::vector<las::Vlr> out;
    for (const auto& v : tile.vlrs()) {
        if (!is_copc_record(v)) out.push_back(v);
        else notes.push_back("COPC info VLR dropped: the output is not a COPC file");
    }
    return out;
}

// Loaded EVLRs of the first tile but its COPC hierarchy and waveform data (never carried: see
// drop_waveforms); the others are named in notes.
std::vector<las::Vlr> kept_evlrs(const dataset::Tile& tile, std::vector<std::string>& notes) {
    std::vector<las::Vlr> out;
    for (const auto& v : tile.evlrs()) {
        if (is_copc_record(v)) notes.push_back("COPC hierarchy EVLR dropped");
        else if (is_waveform_record(v)) notes.push_back(fmt::format("waveform data EVLR ({} B) dropped", v.data_size));
        else if (v.data_loaded) out.push_back(v);
        else notes.push_back(fmt::format("EVLR {} {} ({} bytes) not copied", v.user_id, v.record_id, v.data_size));
    }
    return out;
}

// The output's CRS records: the frame's CRS when a touched tile is reprojected, else the first tile's
// CRS, stated once (pipelines/output_records.hpp; refused unless forced when it cannot be stated as the
// output's point format needs).
void set_output_crs(const dataset::Dataset& ds, std::span<const std::uint32_t> tiles, const ClipRequest& request,
                    las::Header& header, std::vector<las::Vlr>& vlrs, std::vector<las::Vlr>& evlrs,
                    std::vector<std::string>& notes) {
    const std::size_t reprojected = reprojected_count(ds, tiles);
    if (reprojected == 0) {
        std::string forced;
        const auto kept = keep_crs_or_keys(header, vlrs, evlrs, ds.tiles[tiles[0]].tile.crs(), "clip",
                                           tile_name(ds, tiles[0]), request.force, forced);
        notes.insert(notes.end(), kept.begin(), kept.end());
        if (!forced.empty()) notes.push_back(forced + "; the GeoTIFF keys kept");
        return;
    }
    write_crs(header, vlrs, evlrs, ds.frame.crs, "clip");
    notes.push_back(fmt::format("{} of the {} tiles touched reprojected into {}: the output is in that CRS",
                                reprojected, tiles.size(), ds.frame.crs));
}

}  // namespace

ClipResult clip_to_file(const dataset::Dataset& ds, const ClipRequest& request, ThreadPool& pool) {
    const std::vector<std::uint32_t> tiles = tiles_touching(ds, request.region);
    require_touched_tiles(ds, tiles, request.region, request.command, request.where);
    check_tiles_alike(ds, tiles);
    ClipResult result;
    const bool drop_waves = drop_waveforms(ds, tiles, request, result.notes);  // (refused before any output)
    const auto& first = ds.tiles[tiles[0]].tile;
    std::vector<las::Vlr> vlrs = kept_vlrs(first, result.notes), evlrs = kept_evlrs(first, result.notes);
    las::Header header = output_header(first.header);
    const bool reprojected = reprojected_count(ds, tiles) != 0;  // the output is written in the frame's CRS
    if (reprojected) frame_scale_offset(header, ds, tiles, request.region);
    set_output_crs(ds, tiles, request, header, vlrs, evlrs, result.notes);
    laz::LasWriterOptions options;
    options.compress = wants_laz(request.output);
    laz::LasWriter writer(request.output, header, vlrs, options, pool);
    ClipSink sink(writer, ds, reprojected, drop_waves);
    result.read = read_region_points(ds, tiles, request.region, request.filter, pool,
                                     [&](const RegionBatch& b) { sink.add(b); }, request.watch);
    if (result.read.cancelled) throw clip_error("cancelled");  // the writer removes its temporary file
    require_kept_points(ds, tiles, request.region, request.filter, result.read, pool, request.command, request.where);
    const laz::LasWriterResult written = writer.finish(evlrs);
    result.points_written = written.points;
    result.bytes_written = written.bytes_written;
    return result;
}

}  // namespace lidarscout::pipelines
