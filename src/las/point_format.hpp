// Point data record formats 0-10: sizes, which optional fields each has, where they lie in a
// record, and the decoding of one raw record into a Point (raw and scaled coordinates).
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>

namespace lidarscout::las {

struct Header;

struct PointFormatInfo {
    std::uint8_t id = 0;
    std::uint16_t size = 0;   // minimum record length
    bool extended = false;    // formats 6-10 (LAS 1.4 "extended" layout)
    int gps_offset = -1;      // byte offsets in the record, -1 when absent
    int rgb_offset = -1;
    int nir_offset = -1;
    int wave_offset = -1;
};

inline constexpr std::uint8_t kMaxPointFormat = 10;

// Layout of format `id` (0-10); throws Error for unknown formats.
const PointFormatInfo& point_format_info(std::uint8_t id);
bool is_known_point_format(std::uint8_t id);

struct Point {
    std::int32_t X = 0, Y = 0, Z = 0;  // raw integers as stored
    double x = 0, y = 0, z = 0;        // X * scale + offset
    std::uint16_t intensity = 0;
    std::uint8_t return_number = 0;
    std::uint8_t number_of_returns = 0;
    std::uint8_t classification = 0;
    bool synthetic = false, key_point = false, withheld = false, overlap = false;
    std::uint8_t scanner_channel = 0;
    bool scan_direction = false;
    bool edge_of_flight_line = false;
    std::int16_t scan_angle_raw = 0;  // formats 0-5: degrees (int8); 6-10: units of 0.006 degrees
    std::uint8_t user_data = 0;
    std::uint16_t point_source_id = 0;
    double gps_time = 0.0;
    std::array<std::uint16_t, 3> rgb{};
    std::uint16_t nir = 0;

    double scan_angle_degrees(bool extended) const {
        return extended ? scan_angle_raw * 0.006 : static_cast<double>(scan_angle_raw);
    }
};

// Decodes one record of `format` (record.size() >= format.size); scale/offset from header.
Point decode_point(std::span<const std::uint8_t> record, const PointFormatInfo& format,
                   const Header& header);

// Writes `point` as a record of `format` into record[0, format.size) (raw X/Y/Z as stored in
// the point; fields the format lacks are dropped). Values a legacy format cannot hold
// (classification > 31, return numbers > 7, scan angles beyond +-127 degrees) are clamped.
void encode_point(const Point& point, const PointFormatInfo& format, std::span<std::uint8_t> record);

// What converting records lost: per kind, the points holding a value the target format cannot
// (written clamped, or dropped).
struct FormatLosses {
    std::uint64_t classification = 0;  // class above 31 into formats 0-5 (written as 31)
    std::uint64_t returns = 0;         // return number or count above 7 into formats 0-5 (written as 7)
    std::uint64_t scan_angle = 0;      // beyond +-127 degrees into formats 0-5 (clamped)
    std::uint64_t flags = 0;           // overlap flag or scanner channel into formats 0-5 (dropped)
    std::uint64_t gps_time = 0, rgb = 0, nir = 0;  // a value other than 0 into a format without the field

    FormatLosses& operator+=(const FormatLosses& o);
    std::uint64_t total() const;
    // "3 points with a class above 31 (written as 31), ..."; empty when nothing was lost.
    std::string describe() const;
};

// Converts records of one format to another, keeping the extra bytes that follow the base
// record (in_record_length - in.size bytes, moved behind the new base record). What the target
// cannot hold is clamped or dropped (encode_point) and counted in `losses` when given.
void convert_records(std::span<const std::uint8_t> in, const PointFormatInfo& in_format, std::uint16_t in_record_length,
                     std::span<std::uint8_t> out, const PointFormatInfo& out_format, std::uint16_t out_record_length,
                     const Header& header, FormatLosses* losses = nullptr);

}  // namespace lidarscout::las
