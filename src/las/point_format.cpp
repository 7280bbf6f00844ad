// Point data record formats 0-10 (LAS 1.4 R15 tables 7-17) and raw record decoding.
#include "las/point_format.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

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

template <typename T>
void store_le(std::uint8_t* p, T v) {
    std::memcpy(p, &v, sizeof(T));
}

void encode_legacy_bits(const Point& p, std::uint8_t* r) {
    const std::uint8_t ret = std::min<std::uint8_t>(p.return_number, 7);
    const std::uint8_t nret = std::min<std::uint8_t>(p.number_of_returns, 7);
    r[14] = static_cast<std::uint8_t>(ret | (nret << 3) | (p.scan_direction << 6) | (p.edge_of_flight_line << 7));
    r[15] = static_cast<std::uint8_t>(std::min<std::uint8_t>(p.classification, 31) | (p.synthetic << 5) |
                                      (p.key_point << 6) | (p.withheld << 7));
    r[16] = static_cast<std::uint8_t>(static_cast<std::int8_t>(std::clamp<int>(p.scan_angle_raw, -128, 127)));
    r[17] = p.user_data;
    store_le<std::uint16_t>(r + 18, p.point_source_id);
}

void encode_extended_bits(const Point& p, std::uint8_t* r) {
    r[14] = static_cast<std::uint8_t>((p.return_number & 15) | ((p.number_of_returns & 15) << 4));
    r[15] = static_cast<std::uint8_t>(p.synthetic | (p.key_point << 1) | (p.withheld << 2) | (p.overlap << 3) |
                                      ((p.scanner_channel & 3) << 4) | (p.scan_direction << 6) |
                                      (p.edge_of_flight_line << 7));
    r[16] = p.classification;
    r[17] = p.user_data;
    store_le<std::int16_t>(r + 18, p.scan_angle_raw);
    store_le<std::uint16_t>(r + 20, p.point_source_id);
}

// The scan angle in the units of the target layout.
std::int16_t convert_scan_angle(std::int16_t raw, bool from_extended, bool to_extended) {
    if (from_extended == to_extended) return raw;
    if (to_extended) return static_cast<std::int16_t>(std::clamp<long>(std::lround(raw / 0.006), -30000, 30000));
    return static_cast<std::int16_t>(std::clamp<long>(std::lround(raw * 0.006), -128, 127));
}

// Counts what `p` (read from `in`) holds that `out` cannot.
void count_losses(const Point& p, const PointFormatInfo& in, const PointFormatInfo& out, FormatLosses& l) {
    if (in.extended && !out.extended) {
        l.classification += p.classification > 31;
        l.returns += p.return_number > 7 || p.number_of_returns > 7;
        l.scan_angle += std::abs(std::lround(p.scan_angle_raw * 0.006)) > 127;
        l.flags += p.overlap || p.scanner_channel != 0;
    }
    l.gps_time += in.gps_offset >= 0 && out.gps_offset < 0 && p.gps_time != 0.0;
    l.rgb += in.rgb_offset >= 0 && out.rgb_offset < 0 && (p.rgb[0] | p.rgb[1] | p.rgb[2]) != 0;
    l.nir += in.nir_offset >= 0 && out.nir_offset < 0 && p.nir != 0;
}

}  // namespace

FormatLosses& FormatLosses::operator+=(const FormatLosses& o) {
    classification += o.classification, returns += o.returns, scan_angle += o.scan_angle, flags += o.flags;
    gps_time += o.gps_time, rgb += o.rgb, nir += o.nir;
    return *this;
}

std::uint64_t FormatLosses::total() const {
    return classification + returns + scan_angle + flags + gps_time + rgb + nir;
}

std::string FormatLosses::describe() const {
    const std::pair<std::uint64_t, const char*> kinds[] = {
        {classification, "a class above 31 (written as 31)"},
        {returns, "a return number or count above 7 (written as 7)"},
        {scan_angle, "a scan angle beyond 127 degrees (clamped)"},
        {flags, "the overlap flag or a scanner channel (dropped)"},
        {gps_time, "a GPS time (dropped)"},
        {rgb, "a colour (dropped)"},
        {nir, "a NIR value (dropped)"}};
    std::string out;
    for (const auto& [n, what] : kinds) {
        if (n) out += (out.empty() ? "" : ", ") + std::to_string(n) + " points with " + what;
    }
    return out;
}

void encode_point(const Point& p, const PointFormatInfo& format, std::span<std::uint8_t> record) {
    std::uint8_t* r = record.data();
    std::memset(r, 0, format.size);
    store_le<std::int32_t>(r, p.X);
    store_le<std::int32_t>(r + 4, p.Y);
    store_le<std::int32_t>(r + 8, p.Z);
    store_le<std::uint16_t>(r + 12, p.intensity);
    if (format.extended) encode_extended_bits(p, r);
    else encode_legacy_bits(p, r);
    if (format.gps_offset >= 0) store_le<double>(r + format.gps_offset, p.gps_time);
    if (format.rgb_offset >= 0) {
        for (int c = 0; c < 3; ++c) store_le<std::uint16_t>(r + format.rgb_offset + 2 * c, p.rgb[c]);
    }
    if (format.nir_offset >= 0) store_le<std::uint16_t>(r + format.nir_offset, p.nir);
}

void convert_records(std::span<const std::uint8_t> in, const PointFormatInfo& in_format, std::uint16_t in_record_length,
                     std::span<std::uint8_t> out, const PointFormatInfo& out_format, std::uint16_t out_record_length,
                     const Header& header, FormatLosses* losses) {
    const std::size_t n = in.size() / in_record_length;
    const std::size_t extra =
        std::min<std::size_t>(in_record_length - in_format.size, out_record_length - out_format.size);
    if (out.size() != n * out_record_length) throw Error("record conversion: output buffer has the wrong size");
    for (std::size_t i = 0; i < n; ++i) {
        const auto src = in.subspan(i * in_record_length, in_record_length);
        auto dst = out.subspan(i * out_record_length, out_record_length);
        Point p = decode_point(src, in_format, header);
        if (losses) count_losses(p, in_format, out_format, *losses);
        p.scan_angle_raw = convert_scan_angle(p.scan_angle_raw, in_format.extended, out_format.extended);
        encode_point(p, out_format, dst);
        std::fill(dst.begin() + out_format.size, dst.end(), 0);
        std::memcpy(dst.data() + out_format.size, src.data() + in_format.size, extra);
    }
}

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
