// The LAS public header block, versions 1.0-1.5: parsing and validation against the file.
#pragma once

#include <array>
#include <cstdint>
#include <string>

namespace lidarscout::io {
class File;
}

namespace lidarscout::las {

struct Header {
    std::uint16_t file_source_id = 0;
    std::uint16_t global_encoding = 0;
    std::array<std::uint8_t, 16> project_guid{};
    std::uint8_t version_major = 1;
    std::uint8_t version_minor = 2;
    std::string system_identifier;
    std::string generating_software;
    std::uint16_t creation_day = 0;
    std::uint16_t creation_year = 0;
    std::uint16_t header_size = 0;
    std::uint32_t offset_to_point_data = 0;
    std::uint32_t number_of_vlrs = 0;
    std::uint8_t point_format_raw = 0;   // as stored (LAZ sets bit 7, old LAZ bit 6)
    std::uint8_t point_format = 0;       // 0-10, compression bits removed
    bool compressed = false;             // bit 7 or 6 of the stored format was set
    std::uint16_t record_length = 0;
    std::uint32_t legacy_point_count = 0;
    std::array<std::uint32_t, 5> legacy_points_by_return{};
    std::array<double, 3> scale{};
    std::array<double, 3> offset{};
    std::array<double, 3> min{};
    std::array<double, 3> max{};
    // LAS 1.3+
    std::uint64_t waveform_offset = 0;
    // LAS 1.4+
    std::uint64_t evlr_offset = 0;
    std::uint32_t number_of_evlrs = 0;
    std::uint64_t extended_point_count = 0;
    std::array<std::uint64_t, 15> points_by_return{};
    // LAS 1.5+ (when the header is large enough to hold them)
    double max_gps_time = 0.0;
    double min_gps_time = 0.0;
    std::uint16_t time_offset = 0;

    // The number of point records: the 64-bit count of LAS 1.4+ when set, else the legacy one.
    std::uint64_t point_count = 0;

    std::string version_string() const;
    bool at_least(int major, int minor) const {
        return version_major > major || (version_major == major && version_minor >= minor);
    }
};

// Smallest legal header size for a LAS version (227, 235 for 1.3, 375 for 1.4+).
std::uint16_t minimum_header_size(std::uint8_t major, std::uint8_t minor);

// Reads and validates the header of `file`: signature, version, header size, offsets within
// the file, point format and record length, point count vs file size (for uncompressed data).
// Throws lidarscout::Error naming the file, the offset and what is wrong.
Header read_header(const io::File& file);

}  // namespace lidarscout::las
