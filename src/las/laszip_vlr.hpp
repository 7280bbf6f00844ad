// The LASzip VLR ("laszip encoded", record 22204): compressor, coder, versions, options,
// chunk size and the list of compressed items that make up one point record.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace lidarscout::las {

enum class ItemType : std::uint16_t {
    Byte = 0, Short = 1, Integer = 2, Long = 3, Float = 4, Double = 5,
    Point10 = 6, GpsTime11 = 7, Rgb12 = 8, Wavepacket13 = 9,
    Point14 = 10, Rgb14 = 11, RgbNir14 = 12, Wavepacket14 = 13, Byte14 = 14,
};

struct LazItem {
    std::uint16_t type = 0;
    std::uint16_t size = 0;
    std::uint16_t version = 0;

    bool operator==(const LazItem&) const = default;
};

struct LaszipVlr {
    static constexpr std::uint32_t kVariableChunkSize = 0xFFFFFFFFu;

    std::uint16_t compressor = 0;  // 0 none, 1 point-wise, 2 point-wise chunked, 3 layered chunked
    std::uint16_t coder = 0;       // 0 arithmetic
    std::uint8_t version_major = 0;
    std::uint8_t version_minor = 0;
    std::uint16_t version_revision = 0;
    std::uint32_t options = 0;
    std::uint32_t chunk_size = 0;  // kVariableChunkSize: variable-size chunks
    std::int64_t number_of_special_evlrs = -1;
    std::int64_t offset_to_special_evlrs = -1;
    std::vector<LazItem> items;

    // Whether the chunk table stores a point count per chunk. LASzip treats a chunk size of 0
    // like the "variable" marker: its writers then store counts and its reader expects them.
    bool variable_chunks() const { return chunk_size == kVariableChunkSize || chunk_size == 0; }
    bool chunked() const { return compressor == 2 || compressor == 3; }
    std::uint32_t record_length() const;  // sum of item sizes
    bool operator==(const LaszipVlr&) const = default;
};

// Name of an item type ("POINT10", ...), or "UNKNOWN".
const char* item_type_name(std::uint16_t type);

// Parses and validates the VLR payload; `file` and `offset` (the payload's file offset) are
// for error messages. Rejects unknown compressors, coders, item types and item versions.
LaszipVlr parse_laszip_vlr(std::span<const std::uint8_t> payload, const std::string& file,
                           std::uint64_t offset);

}  // namespace lidarscout::las
