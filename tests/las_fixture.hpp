// Small LAS files made by the tests with our own writer: given points in an EPSG CRS (GeoTIFF keys;
// projected, or longitude/latitude), for the DEM and reprojection tests.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "core/thread_pool.hpp"
#include "dataset/dataset.hpp"
#include "dataset/point_reader.hpp"
#include "io/file.hpp"
#include "las/crs_records.hpp"
#include "las/header_writer.hpp"
#include "las/point_format.hpp"
#include "las/vlr.hpp"
#include "laz/laz.hpp"

namespace lidarscout::test {

struct FixturePoint {
    double x = 0, y = 0, z = 0;
    std::uint8_t classification = 2;
    std::uint16_t r = 0, g = 0, b = 0;  // 8-bit values (as many files store them)
};

// A GeoTIFF key directory (LASF_Projection 34735): a projected CRS `epsg` in its own units,
// with the vertical CRS `vertical_epsg` when it is not 0 (a compound CRS).
inline las::Vlr epsg_vlr(int epsg, int vertical_epsg = 0) { return las::geotiff_epsg_vlr(epsg, vertical_epsg); }

// A fixture's CRS (GeoTIFF keys of EPSG codes; none when epsg is 0) and x/y scale.
struct FixtureCrs {
    int epsg = 0, vertical_epsg = 0;
    bool geographic = false;  // x/y are longitude/latitude degrees
    double xy_scale = 0.001;
};

// Writes `points` as a LAS 1.2 file of point format 2 (with colour), scale crs.xy_scale (z 1 mm),
// header bounds from the points, CRS `crs`; LAZ with `chunk_size`-point chunks when `compress`.
inline void write_fixture(const std::string& path, const std::vector<FixturePoint>& points, const FixtureCrs& crs,
                          bool compress = false, std::uint32_t chunk_size = 50'000) {
    las::Header h;
    h.version_major = 1;
    h.version_minor = 2;
    h.header_size = las::standard_header_size(1, 2);
    h.point_format = 2;
    h.record_length = las::point_format_info(2).size;
    h.scale = {crs.xy_scale, crs.xy_scale, 0.001};
    h.offset = {points.empty() ? 0.0 : std::floor(points[0].x), points.empty() ? 0.0 : std::floor(points[0].y), 0.0};
    h.generating_software = "lidarscout tests";
    std::vector<las::Vlr> vlrs;
    if (crs.epsg) vlrs.push_back(las::geotiff_epsg_vlr(crs.epsg, crs.vertical_epsg, crs.geographic));
    ThreadPool pool(1);
    laz::LasWriter writer(path, h, vlrs, {compress, chunk_size, false}, pool);
    const auto& f = las::point_format_info(2);
    std::vector<std::uint8_t> record(f.size);
    std::array<double, 3> lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
    for (const auto& p : points) {
        las::Point q;
        const double xyz[3] = {p.x, p.y, p.z};
        std::int32_t* raw[3] = {&q.X, &q.Y, &q.Z};
        for (int a = 0; a < 3; ++a) {
            *raw[a] = static_cast<std::int32_t>(std::llround((xyz[a] - h.offset[a]) / h.scale[a]));
            const double stored = *raw[a] * h.scale[a] + h.offset[a];
            lo[a] = std::min(lo[a], stored);
            hi[a] = std::max(hi[a], stored);
        }
        q.return_number = q.number_of_returns = 1;
        q.classification = p.classification;
        q.rgb = {p.r, p.g, p.b};
        las::encode_point(q, f, record);
        writer.add(record);
    }
    writer.header().min = lo;
    writer.header().max = hi;
    writer.finish();
}

// The same in the projected CRS `epsg` (0: none; + `vertical_epsg` if not 0), scale 1 mm.
inline void write_fixture(const std::string& path, const std::vector<FixturePoint>& points, int epsg,
                          bool compress = false, std::uint32_t chunk_size = 50'000, int vertical_epsg = 0) {
    write_fixture(path, points, FixtureCrs{epsg, vertical_epsg}, compress, chunk_size);
}

// Every point of a one-tile dataset as stored (x, y, z in the file's units).
inline std::vector<std::array<double, 3>> read_points_back(const dataset::Dataset& ds) {
    std::vector<std::array<double, 3>> out;
    ThreadPool pool(1);
    const auto& t = ds.tiles.at(0);
    const auto file = io::File::open(t.tile.path());
    const auto& f = las::point_format_info(t.tile.header.point_format);
    dataset::for_each_record_batch(file, t.tile, pool, [&](std::uint64_t, std::span<const std::uint8_t> records) {
        for (std::size_t k = 0; k + t.tile.header.record_length <= records.size(); k += t.tile.header.record_length) {
            const auto p = las::decode_point(records.subspan(k, t.tile.header.record_length), f, t.tile.header);
            out.push_back({p.x, p.y, p.z});
        }
    });
    return out;
}

}  // namespace lidarscout::test
