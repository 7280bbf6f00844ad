// Reading and validating the LAS public header block (versions 1.0-1.5).
#include "las/header.hpp"

#include <cmath>
#include <vector>

#include "core/error.hpp"
#include "io/byte_reader.hpp"
#include "io/file.hpp"
#include "las/point_format.hpp"

namespace lidarscout::las {
namespace {

constexpr std::size_t kLegacyHeaderSize = 227;
constexpr std::size_t kLargestKnownHeader = 393;  // LAS 1.5

[[noreturn]] void fail(const io::File& file, std::uint64_t offset, const std::string& cause) {
    throw Error(file.path(), offset, cause);
}

void check_signature(const io::File& file) {
    std::uint8_t sig[4] = {};
    if (file.size() < 4 || file.read_at(0, sig) < 4 || std::string(reinterpret_cast<char*>(sig), 4) != "LASF") {
        fail(file, 0, file.size() == 0 ? "not a LAS/LAZ file: the file is empty"
                                       : "not a LAS/LAZ file: no 'LASF' signature");
    }
}

void parse_legacy_part(io::ByteReader& r, Header& h) {
    r.skip(4, "signature");
    h.file_source_id = r.u16("file source id");
    h.global_encoding = r.u16("global encoding");
    auto guid = r.bytes(16, "project GUID");
    std::copy(guid.begin(), guid.end(), h.project_guid.begin());
    h.version_major = r.u8("version major");
    h.version_minor = r.u8("version minor");
    h.system_identifier = r.fixed_string(32, "system identifier");
    h.generating_software = r.fixed_string(32, "generating software");
    h.creation_day = r.u16("creation day");
    h.creation_year = r.u16("creation year");
    h.header_size = r.u16("header size");
    h.offset_to_point_data = r.u32("offset to point data");
    h.number_of_vlrs = r.u32("number of VLRs");
    h.point_format_raw = r.u8("point data format");
    h.record_length = r.u16("point data record length");
    h.legacy_point_count = r.u32("number of point records");
    for (auto& n : h.legacy_points_by_return) n = r.u32("points by return");
    for (auto& s : h.scale) s = r.f64("scale factor");
    for (auto& o : h.offset) o = r.f64("offset");
    for (int i = 0; i < 3; ++i) {
        h.max[i] = r.f64("bounds");
        h.min[i] = r.f64("bounds");
    }
}

// Fields of LAS 1.3, 1.4 and 1.5, each read only when the declared header holds them.
void parse_extended_part(io::ByteReader& r, Header& h) {
    if (h.at_least(1, 3) && h.header_size >= 235) h.waveform_offset = r.u64("waveform data offset");
    if (h.at_least(1, 4) && h.header_size >= 375) {
        h.evlr_offset = r.u64("EVLR offset");
        h.number_of_evlrs = r.u32("number of EVLRs");
        h.extended_point_count = r.u64("number of point records (64-bit)");
        for (auto& n : h.points_by_return) n = r.u64("points by return (64-bit)");
    }
    if (h.at_least(1, 5) && h.header_size >= 393) {
        h.max_gps_time = r.f64("max GPS time");
        h.min_gps_time = r.f64("min GPS time");
        h.time_offset = r.u16("time offset");
    }
}

void validate_layout(const io::File& file, const Header& h) {
    if (h.version_major != 1 || h.version_minor > 5) {
        fail(file, 24, "unsupported LAS version " + h.version_string());
    }
    const auto min_size = minimum_header_size(h.version_major, h.version_minor);
    if (h.header_size < min_size) {
        fail(file, 94, "header size " + std::to_string(h.header_size) + " is smaller than the " +
                           std::to_string(min_size) + " bytes LAS " + h.version_string() + " requires");
    }
    if (h.header_size > file.size()) {
        fail(file, 94, "header size " + std::to_string(h.header_size) + " is beyond the end of the file (" +
                           std::to_string(file.size()) + " bytes)");
    }
    if (h.offset_to_point_data < h.header_size) {
        fail(file, 96, "offset to point data " + std::to_string(h.offset_to_point_data) +
                           " lies inside the header (" + std::to_string(h.header_size) + " bytes)");
    }
    if (h.offset_to_point_data > file.size()) {
        fail(file, 96, "offset to point data " + std::to_string(h.offset_to_point_data) +
                           " is beyond the end of the file (" + std::to_string(file.size()) + " bytes)");
    }
    if (h.number_of_evlrs > 0 && (h.evlr_offset < h.offset_to_point_data || h.evlr_offset > file.size())) {
        fail(file, 235,
             "EVLR offset " + std::to_string(h.evlr_offset) + " lies outside the point data end .. file end (" +
                 std::to_string(h.offset_to_point_data) + " .. " + std::to_string(file.size()) + ")");
    }
}

void validate_format(const io::File& file, const Header& h) {
    if (!is_known_point_format(h.point_format)) {
        fail(file, 104, "unknown point data record format " + std::to_string(h.point_format));
    }
    const auto& fmt = point_format_info(h.point_format);
    if (h.record_length < fmt.size) {
        fail(file, 105, "point record length " + std::to_string(h.record_length) + " is too short for point format " +
                            std::to_string(h.point_format) + " (needs at least " + std::to_string(fmt.size) + ")");
    }
    for (int i = 0; i < 3; ++i) {
        if (!std::isfinite(h.scale[i]) || h.scale[i] == 0.0) {
            fail(file, 131 + 8 * i, "scale factor " + std::to_string(h.scale[i]) + " is not a usable number");
        }
        if (!std::isfinite(h.offset[i])) fail(file, 155 + 8 * i, "offset is not a finite number");
    }
}

// For uncompressed data the records must fit between the point data offset and the end of
// the point data (the EVLRs when there are some, else the end of the file).
void validate_point_count(const io::File& file, const Header& h) {
    if (h.compressed) return;  // LAZ: checked against the chunk table
    std::uint64_t end = file.size();
    if (h.number_of_evlrs > 0 && h.evlr_offset >= h.offset_to_point_data) end = h.evlr_offset;
    const std::uint64_t whole_records = (end - h.offset_to_point_data) / h.record_length;
    if (h.point_count > whole_records) {
        fail(file, h.offset_to_point_data,
             "header announces " + std::to_string(h.point_count) + " points of " + std::to_string(h.record_length) +
                 " bytes but the file holds only " + std::to_string(whole_records) + " whole records");
    }
}

}  // namespace

std::string Header::version_string() const {
    return std::to_string(version_major) + "." + std::to_string(version_minor);
}

std::uint16_t minimum_header_size(std::uint8_t major, std::uint8_t minor) {
    if (major == 1 && minor >= 4) return 375;
    if (major == 1 && minor == 3) return 235;
    return static_cast<std::uint16_t>(kLegacyHeaderSize);
}

Header read_header(const io::File& file) {
    check_signature(file);
    if (file.size() < kLegacyHeaderSize) {
        fail(file, 0,
             "truncated header: the file has " + std::to_string(file.size()) + " bytes, a LAS header needs at least " +
                 std::to_string(kLegacyHeaderSize));
    }
    std::vector<std::uint8_t> buf(std::min<std::uint64_t>(file.size(), kLargestKnownHeader));
    file.read_exact(0, buf, "header");
    io::ByteReader r(buf, 0, file.path());

    Header h;
    parse_legacy_part(r, h);
    validate_layout(file, h);
    r.seek(kLegacyHeaderSize);
    parse_extended_part(r, h);

    h.point_format = h.point_format_raw & 0x3F;
    h.compressed = (h.point_format_raw & 0xC0) != 0;
    h.point_count = (h.at_least(1, 4) && h.extended_point_count != 0) ? h.extended_point_count : h.legacy_point_count;
    validate_format(file, h);
    validate_point_count(file, h);
    return h;
}

}  // namespace lidarscout::las
