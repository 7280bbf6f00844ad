// Serialisation of LAS headers and (E)VLRs (little-endian, fixed layouts).
#include "las/header_writer.hpp"

#include <cstring>
#include <string>

#include "core/error.hpp"
#include "las/point_format.hpp"

namespace lidarscout::las {
namespace {

class ByteWriter {
public:
    explicit ByteWriter(std::vector<std::uint8_t>& out) : out_(out) {}
    template <typename T>
    void put(T v) {
        const auto at = out_.size();
        out_.resize(at + sizeof(T));
        std::memcpy(out_.data() + at, &v, sizeof(T));
    }
    void fixed_string(const std::string& s, std::size_t n) {
        for (std::size_t i = 0; i < n; ++i) out_.push_back(i < s.size() ? static_cast<std::uint8_t>(s[i]) : 0);
    }
    void bytes(std::span<const std::uint8_t> b) { out_.insert(out_.end(), b.begin(), b.end()); }

private:
    std::vector<std::uint8_t>& out_;
};

void write_legacy_part(ByteWriter& w, const Header& h) {
    w.fixed_string("LASF", 4);
    w.put(h.file_source_id);
    w.put(h.global_encoding);
    w.bytes(h.project_guid);
    w.put(h.version_major);
    w.put(h.version_minor);
    w.fixed_string(h.system_identifier, 32);
    w.fixed_string(h.generating_software, 32);
    w.put(h.creation_day);
    w.put(h.creation_year);
    w.put(h.header_size);
    w.put(h.offset_to_point_data);
    w.put(h.number_of_vlrs);
    w.put(static_cast<std::uint8_t>(h.point_format | (h.compressed ? 0x80 : 0)));
    w.put(h.record_length);
    w.put(h.legacy_point_count);
    for (auto n : h.legacy_points_by_return) w.put(n);
    for (auto s : h.scale) w.put(s);
    for (auto o : h.offset) w.put(o);
    for (int i = 0; i < 3; ++i) {
        w.put(h.max[i]);
        w.put(h.min[i]);
    }
}

void write_extended_part(ByteWriter& w, const Header& h) {
    if (h.at_least(1, 3)) w.put(h.waveform_offset);
    if (h.at_least(1, 4)) {
        w.put(h.evlr_offset);
        w.put(h.number_of_evlrs);
        w.put(h.extended_point_count);
        for (auto n : h.points_by_return) w.put(n);
    }
    if (h.at_least(1, 5)) {
        w.put(h.max_gps_time);
        w.put(h.min_gps_time);
        w.put(h.time_offset);
    }
}

}  // namespace

std::uint16_t standard_header_size(std::uint8_t major, std::uint8_t minor) {
    if (major == 1 && minor >= 5) return 393;
    return minimum_header_size(major, minor);
}

std::vector<std::uint8_t> serialize_header(const Header& header, std::span<const std::uint8_t> trailing) {
    const auto standard = standard_header_size(header.version_major, header.version_minor);
    if (header.header_size < standard) {
        throw Error("cannot write a LAS " + header.version_string() + " header of " +
                    std::to_string(header.header_size) + " bytes (needs " + std::to_string(standard) + ")");
    }
    std::vector<std::uint8_t> out;
    out.reserve(header.header_size);
    ByteWriter w(out);
    write_legacy_part(w, header);
    write_extended_part(w, header);
    const std::size_t extra = header.header_size - out.size();
    w.bytes(trailing.first(std::min(extra, trailing.size())));
    out.resize(header.header_size, 0);
    return out;
}

void set_point_count(Header& h, std::uint64_t count) {
    h.point_count = count;
    h.extended_point_count = h.at_least(1, 4) ? count : 0;
    const bool legacy_ok = h.point_format <= 5 && count <= 0xFFFFFFFFu;
    h.legacy_point_count = legacy_ok ? static_cast<std::uint32_t>(count) : 0;
    if (!legacy_ok) h.legacy_points_by_return.fill(0);
}

std::vector<std::uint8_t> serialize_vlr(const Vlr& vlr) {
    const auto& payload = vlr.data;
    if (!vlr.extended && payload.size() > 0xFFFF) {
        throw Error("VLR '" + vlr.user_id + "' " + std::to_string(vlr.record_id) + " payload of " +
                    std::to_string(payload.size()) + " bytes does not fit a VLR (max 65535)");
    }
    std::vector<std::uint8_t> out;
    ByteWriter w(out);
    w.put(std::uint16_t{0});
    w.fixed_string(vlr.user_id, 16);
    w.put(vlr.record_id);
    if (vlr.extended) w.put(static_cast<std::uint64_t>(payload.size()));
    else w.put(static_cast<std::uint16_t>(payload.size()));
    w.fixed_string(vlr.description, 32);
    w.bytes(payload);
    return out;
}

}  // namespace lidarscout::las
