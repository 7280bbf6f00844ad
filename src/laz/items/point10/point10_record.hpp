// The 20-byte POINT10 item (the core of LAS point formats 0-5) as the v1 and v2 decoders
// keep it between points, with its byte layout and the bit fields they use as contexts.
#pragma once

#include <cstdint>
#include <cstring>

namespace lidarscout::laz::detail::point10 {

inline constexpr std::size_t kPoint10Size = 20;

// Field order and widths match the record bytes exactly, so it is copied as a whole.
struct Point10Record {
    std::int32_t x = 0;
    std::int32_t y = 0;
    std::int32_t z = 0;
    std::uint16_t intensity = 0;
    std::uint8_t return_flags = 0;  // return number (3), number of returns (3), scan dir, edge
    std::uint8_t classification = 0;
    std::uint8_t scan_angle = 0;    // signed in LAS; the predictors treat it as a byte
    std::uint8_t user_data = 0;
    std::uint16_t point_source = 0;

    static Point10Record load(const std::uint8_t* bytes) {
        Point10Record r;
        std::memcpy(&r, bytes, kPoint10Size);
        return r;
    }
    void store(std::uint8_t* bytes) const { std::memcpy(bytes, this, kPoint10Size); }

    std::uint32_t return_number() const { return return_flags & 7u; }
    std::uint32_t number_of_returns() const { return (return_flags >> 3) & 7u; }
    std::uint32_t scan_direction() const { return (return_flags >> 6) & 1u; }
};
static_assert(sizeof(Point10Record) == kPoint10Size, "Point10Record must match the record layout");

}  // namespace lidarscout::laz::detail::point10
