// Writing the LAS container: the public header block (any version 1.0-1.5) and VLR / EVLR
// records, byte for byte as read_header / read_vlrs / read_evlrs read them.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "las/header.hpp"
#include "las/vlr.hpp"

namespace lidarscout::las {

// header.header_size bytes: the fields of header's version at their standard places, then
// (when header_size is larger than the standard size) `trailing` bytes, zero-padded.
// Writes point_format | 0x80 when header.compressed. Legacy point counts are written as
// they are in `header` (see set_point_count).
std::vector<std::uint8_t> serialize_header(const Header& header, std::span<const std::uint8_t> trailing = {});

// Sets the point count fields for the header's version and format: the 64-bit count
// (LAS 1.4+), and the legacy 32-bit count where it can hold it (0 otherwise, or always 0
// for formats 6-10 as LAS 1.4 asks).
void set_point_count(Header& header, std::uint64_t count);

// A VLR (54-byte record header + payload; payload < 64 KiB) or an EVLR (60 + payload).
std::vector<std::uint8_t> serialize_vlr(const Vlr& vlr);

// The standard size of the header of a version (227, 235, 375; 1.5: 393).
std::uint16_t standard_header_size(std::uint8_t major, std::uint8_t minor);

}  // namespace lidarscout::las
