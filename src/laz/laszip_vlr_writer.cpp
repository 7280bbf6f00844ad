// LASzip VLR construction and serialisation (see laszip_vlr_writer.hpp).
#include "laz/laszip_vlr_writer.hpp"

#include <string>
#include <type_traits>

#include "core/error.hpp"
#include "las/point_format.hpp"

namespace lidarscout::laz {
namespace {

using las::ItemType;
using las::LazItem;

constexpr std::uint16_t kPointwiseChunked = 2;
constexpr std::uint16_t kLayeredChunked = 3;
constexpr std::uint16_t kArithmeticCoder = 0;
// Item versions LASzip writes by default (LAS 1.4 and older).
constexpr std::uint16_t kPoint10Version = 2;
constexpr std::uint16_t kWavepacket13Version = 1;
constexpr std::uint16_t kPoint14Version = 3;

LazItem item(ItemType type, std::size_t size, std::uint16_t version) {
    return {static_cast<std::uint16_t>(type), static_cast<std::uint16_t>(size), version};
}

std::vector<LazItem> point10_items(const las::PointFormatInfo& f, std::size_t extra_bytes) {
    std::vector<LazItem> items{item(ItemType::Point10, 20, kPoint10Version)};
    if (f.gps_offset >= 0) items.push_back(item(ItemType::GpsTime11, 8, kPoint10Version));
    if (f.rgb_offset >= 0) items.push_back(item(ItemType::Rgb12, 6, kPoint10Version));
    if (f.wave_offset >= 0) items.push_back(item(ItemType::Wavepacket13, 29, kWavepacket13Version));
    if (extra_bytes > 0) items.push_back(item(ItemType::Byte, extra_bytes, kPoint10Version));
    return items;
}

std::vector<LazItem> point14_items(const las::PointFormatInfo& f, std::size_t extra_bytes) {
    std::vector<LazItem> items{item(ItemType::Point14, 30, kPoint14Version)};
    if (f.nir_offset >= 0) {
        items.push_back(item(ItemType::RgbNir14, 8, kPoint14Version));
    } else if (f.rgb_offset >= 0) {
        items.push_back(item(ItemType::Rgb14, 6, kPoint14Version));
    }
    if (f.wave_offset >= 0) items.push_back(item(ItemType::Wavepacket14, 29, kPoint14Version));
    if (extra_bytes > 0) items.push_back(item(ItemType::Byte14, extra_bytes, kPoint14Version));
    return items;
}

template <class T>
void append_le(std::vector<std::uint8_t>& out, T v) {
    const auto u = static_cast<std::make_unsigned_t<T>>(v);
    for (std::size_t i = 0; i < sizeof(T); ++i) out.push_back(static_cast<std::uint8_t>(u >> (8 * i)));
}

}  // namespace

las::LaszipVlr make_laszip_vlr(std::uint8_t point_format, std::uint16_t record_length, std::uint32_t chunk_size) {
    if (!las::is_known_point_format(point_format)) {
        throw Error("LAZ writer: unknown point format " + std::to_string(point_format));
    }
    const las::PointFormatInfo& f = las::point_format_info(point_format);
    if (record_length < f.size) {
        throw Error("LAZ writer: record length " + std::to_string(record_length) + " is shorter than the " +
                    std::to_string(f.size) + " bytes of point format " + std::to_string(point_format));
    }
    if (chunk_size == 0) throw Error("LAZ writer: chunk size 0 (use the variable chunk size marker instead)");

    las::LaszipVlr laz;
    laz.compressor = f.extended ? kLayeredChunked : kPointwiseChunked;
    laz.coder = kArithmeticCoder;
    laz.version_major = kWriterVersionMajor;
    laz.version_minor = kWriterVersionMinor;
    laz.version_revision = kWriterVersionRevision;
    laz.options = 0;
    laz.chunk_size = chunk_size;
    laz.number_of_special_evlrs = -1;
    laz.offset_to_special_evlrs = -1;
    const std::size_t extra_bytes = record_length - f.size;
    laz.items = f.extended ? point14_items(f, extra_bytes) : point10_items(f, extra_bytes);
    return laz;
}

std::vector<std::uint8_t> serialize_laszip_vlr(const las::LaszipVlr& laz) {
    std::vector<std::uint8_t> out;
    out.reserve(34 + 6 * laz.items.size());
    append_le(out, laz.compressor);
    append_le(out, laz.coder);
    append_le(out, laz.version_major);
    append_le(out, laz.version_minor);
    append_le(out, laz.version_revision);
    append_le(out, laz.options);
    append_le(out, laz.chunk_size);
    append_le(out, laz.number_of_special_evlrs);
    append_le(out, laz.offset_to_special_evlrs);
    append_le(out, static_cast<std::uint16_t>(laz.items.size()));
    for (const LazItem& i : laz.items) {
        append_le(out, i.type);
        append_le(out, i.size);
        append_le(out, i.version);
    }
    return out;
}

}  // namespace lidarscout::laz
