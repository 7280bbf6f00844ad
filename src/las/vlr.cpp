// Reading VLRs (54-byte headers in the header area) and EVLRs (60-byte headers after the
// point data), with checks that no record overruns its area.
#include "las/vlr.hpp"

#include <algorithm>

#include "core/error.hpp"
#include "io/byte_reader.hpp"
#include "io/file.hpp"
#include "las/header.hpp"

namespace lidarscout::las {
namespace {

constexpr std::size_t kVlrHeaderSize = 54;
constexpr std::size_t kEvlrHeaderSize = 60;

Vlr parse_record_header(io::ByteReader& r, bool extended) {
    Vlr v;
    v.extended = extended;
    v.header_offset = r.file_offset();
    r.skip(2, "VLR reserved field");
    v.user_id = r.fixed_string(16, "VLR user id");
    v.record_id = r.u16("VLR record id");
    v.data_size = extended ? r.u64("EVLR record length") : r.u16("VLR record length");
    v.description = r.fixed_string(32, "VLR description");
    v.data_offset = r.file_offset();
    return v;
}

std::string describe(const Vlr& v, std::size_t index) {
    return std::string(v.extended ? "EVLR " : "VLR ") + std::to_string(index) + " ('" + v.user_id + "' " +
           std::to_string(v.record_id) + ")";
}

}  // namespace

std::vector<Vlr> read_vlrs(const io::File& file, const Header& header, Diagnostics* warnings) {
    const std::uint64_t begin = header.header_size;
    const std::uint64_t end = header.offset_to_point_data;
    auto area = file.read_vector(begin, end - begin, "VLR area");
    io::ByteReader r(area, begin, file.path());
    std::vector<Vlr> vlrs;
    vlrs.reserve(std::min<std::uint64_t>(header.number_of_vlrs, area.size() / kVlrHeaderSize));
    for (std::uint32_t i = 0; i < header.number_of_vlrs; ++i) {
        if (r.remaining() < kVlrHeaderSize) {
            if (warnings) {
                warnings->warn("header announces " + std::to_string(header.number_of_vlrs) + " VLRs but only " +
                                    std::to_string(i) + " fit before the point data; the rest are ignored");
            }
            break;
        }
        Vlr v = parse_record_header(r, false);
        if (v.data_size > r.remaining()) {
            throw Error(file.path(), v.header_offset,
                        describe(v, i) + " payload of " + std::to_string(v.data_size) +
                            " bytes overruns the start of the point data at " + std::to_string(end));
        }
        auto payload = r.bytes(v.data_size);
        v.data.assign(payload.begin(), payload.end());
        v.data_loaded = true;
        vlrs.push_back(std::move(v));
    }
    return vlrs;
}

std::vector<Vlr> read_evlrs(const io::File& file, const Header& header) {
    std::vector<Vlr> evlrs;
    if (header.number_of_evlrs == 0) return evlrs;
    std::uint64_t pos = header.evlr_offset;
    if (header.number_of_evlrs > (file.size() - pos) / kEvlrHeaderSize) {
        throw Error(file.path(), pos,
                    "header announces " + std::to_string(header.number_of_evlrs) + " EVLRs but only " +
                        std::to_string(file.size() - pos) + " bytes follow the EVLR offset");
    }
    for (std::uint32_t i = 0; i < header.number_of_evlrs; ++i) {
        auto head = file.read_vector(pos, kEvlrHeaderSize, "EVLR header");
        io::ByteReader r(head, pos, file.path());
        Vlr v = parse_record_header(r, true);
        if (v.data_size > file.size() - v.data_offset) {
            throw Error(file.path(), v.header_offset,
                        describe(v, i) + " payload of " + std::to_string(v.data_size) +
                            " bytes overruns the end of the file (" + std::to_string(file.size()) + " bytes)");
        }
        if (v.data_size <= kEvlrEagerLoadLimit) {
            v.data = file.read_vector(v.data_offset, v.data_size, "EVLR payload");
            v.data_loaded = true;
        }
        pos = v.data_offset + v.data_size;
        evlrs.push_back(std::move(v));
    }
    return evlrs;
}

const Vlr* find_vlr(const std::vector<Vlr>& vlrs, const char* user, std::uint16_t id) {
    for (const auto& v : vlrs) {
        if (v.is(user, id)) return &v;
    }
    return nullptr;
}

std::vector<std::uint8_t> vlr_payload(const io::File& file, const Vlr& vlr) {
    if (vlr.data_loaded) return vlr.data;
    return file.read_vector(vlr.data_offset, vlr.data_size, "EVLR payload");
}

}  // namespace lidarscout::las
