// Point data record formats 0-10 (LAS 1.4 R15 tables 7-17) and raw record decoding.
#include "las/point_format.hpp"

#include "core/error.hpp"
#include "io/byte_reader.hpp"
#include "las/header.hpp"

namespace lidarscout::las {
namespace {

using io::load_le;

// id, size, extended, gps, rgb, nir, wave
constexpr std::array<PointFormatInfo, 11> kFormats{{
    {0, 20, false, -1, -1, -1, -1},
    {1, 28, false, 20, -1, -1, -1},
    {2, 26, false, -1, 20, -1, -1},
    {3, 34, false, 20, 28, -1, -1},
    {4, 57, false, 20, -1, -1, 28},
    {5, 63, false, 20, 28, -1, 34},
    {6, 30, true, 22, -1, -1, -1},
    {7, 36, true, 22, 30, -1, -1},
    {8, 38, true, 22, 30, 36, -1},
    {9, 59, true, 22, -1, -1, 30},
    {10, 67, true, 22, 30, 36, 38},
}};

void decode_legacy_bits(const std::uint8_t* r, Point& p) {
    const std::uint8_t returns = r[14];
    p.return_number = returns & 7;
    p.number_of_returns = (returns >> 3) & 7;
    p.scan_direction = (returns >> 6) & 1;
    p.edge_of_flight_line = (returns >> 7) & 1;
    const std::uint8_t cls = r[15];
    p.classification = cls & 31;
    p.synthetic = (cls >> 5) & 1;
    p.key_point = (cls >> 6) & 1;
    p.withheld = (cls >> 7) & 1;
    p.scan_angle_raw = static_cast<std::int8_t>(r[16]);
    p.user_data = r[17];
    p.point_source_id = load_le<std::uint16_t>(r + 18);
}

void decode_extended_bits(const std::uint8_t* r, Point& p) {
    const std::uint8_t returns = r[14];
    p.return_number = returns & 15;
    p.number_of_returns = (returns >> 4) & 15;
    const std::uint8_t flags = r[15];
    p.synthetic = flags & 1;
    p.key_point = (flags >> 1) & 1;
    p.withheld = (flags >> 2) & 1;
    p.overlap = (flags >> 3) & 1;
    p.scanner_channel = (flags >> 4) & 3;
    p.scan_direction = (flags >> 6) & 1;
    p.edge_of_flight_line = (flags >> 7) & 1;
    p.classification = r[16];
    p.user_data = r[17];
    p.scan_angle_raw = load_le<std::int16_t>(r + 18);
    p.point_source_id = load_le<std::uint16_t>(r + 20);
}

}  // namespace

bool is_known_point_format(std::uint8_t id) { return id <= kMaxPointFormat; }

const PointFormatInfo& point_format_info(std::uint8_t id) {
    if (!is_known_point_format(id)) throw Error("unknown point data record format " + std::to_string(id));
    return kFormats[id];
}

Point decode_point(std::span<const std::uint8_t> record, const PointFormatInfo& format,
                   const Header& header) {
    const std::uint8_t* r = record.data();
    Point p;
    p.X = load_le<std::int32_t>(r);
    p.Y = load_le<std::int32_t>(r + 4);
    p.Z = load_le<std::int32_t>(r + 8);
    p.x = p.X * header.scale[0] + header.offset[0];
    p.y = p.Y * header.scale[1] + header.offset[1];
    p.z = p.Z * header.scale[2] + header.offset[2];
    p.intensity = load_le<std::uint16_t>(r + 12);
    if (format.extended) decode_extended_bits(r, p);
    else decode_legacy_bits(r, p);
    if (format.gps_offset >= 0) p.gps_time = load_le<double>(r + format.gps_offset);
    if (format.rgb_offset >= 0) {
        for (int c = 0; c < 3; ++c) p.rgb[c] = load_le<std::uint16_t>(r + format.rgb_offset + 2 * c);
    }
    if (format.nir_offset >= 0) p.nir = load_le<std::uint16_t>(r + format.nir_offset);
    return p;
}

}  // namespace lidarscout::las
