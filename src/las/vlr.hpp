// Variable length records (VLRs, in the header area) and extended VLRs (EVLRs, after the
// point data, LAS 1.3+/1.4): their headers, payload location and (for small ones) payload.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/diagnostic.hpp"

namespace lidarscout::io {
class File;
}

namespace lidarscout::las {

struct Header;

struct Vlr {
    std::string user_id;      // 16 chars, NUL-trimmed, e.g. "LASF_Projection", "laszip encoded"
    std::uint16_t record_id = 0;
    std::string description;  // 32 chars, NUL-trimmed
    bool extended = false;    // true for an EVLR
    std::uint64_t header_offset = 0;  // file offset of the record header
    std::uint64_t data_offset = 0;    // file offset of the payload
    std::uint64_t data_size = 0;      // payload bytes
    bool data_loaded = false;         // payload in `data` (always for VLRs; small EVLRs)
    std::vector<std::uint8_t> data;

    bool is(const char* user, std::uint16_t id) const { return user_id == user && record_id == id; }
    bool operator==(const Vlr&) const = default;
};

// Payloads of EVLRs above this size are not loaded eagerly (waveform data, big hierarchies).
inline constexpr std::uint64_t kEvlrEagerLoadLimit = 4u << 20;

// Reads the VLRs that follow the header; throws Error if one overruns the point data. When
// the header announces more VLRs than there is room for before the point data (a common
// writer bug), reading stops at the point data and a warning is added to `warnings`.
std::vector<Vlr> read_vlrs(const io::File& file, const Header& header, Diagnostics* warnings = nullptr);
// Reads the EVLRs (LAS 1.4) at header.evlr_offset; throws Error if one overruns the file.
std::vector<Vlr> read_evlrs(const io::File& file, const Header& header);

// First record with this user id and record id in `vlrs`, or nullptr.
const Vlr* find_vlr(const std::vector<Vlr>& vlrs, const char* user, std::uint16_t id);

// The payload of `vlr`, loaded from `file` if it was not loaded eagerly.
std::vector<std::uint8_t> vlr_payload(const io::File& file, const Vlr& vlr);

}  // namespace lidarscout::las
