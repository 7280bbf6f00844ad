// Which points a user works with: classes (any code 0-255), return kinds (first, last, single,
// intermediate) and an intensity range, as the viewer's Filters section and the CLI's --classes,
// --returns and --intensity set them (class names: las/classification.hpp); the presets (ground ...);
// and counts per class and return kind of the points seen.
#pragma once

#include <array>
#include <bitset>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>

namespace lidarscout::las {
struct Point;
}

namespace lidarscout::dataset {

// Return kinds, a bit each. With r the return number and n the number of returns of a point:
// first r = 1, last r = n, single n = 1, intermediate 1 < r < n. A point may be several (a single
// return is first and last). Return numbers or counts of 0 (invalid, yet met) count as 1, and a
// count below its number as that number.
namespace returns {
inline constexpr std::uint8_t kFirst = 1, kLast = 2, kSingle = 4, kIntermediate = 8;
inline constexpr std::uint8_t kAny = kFirst | kLast | kSingle | kIntermediate;
// The kinds a point with return number `r` of `n` is.
std::uint8_t kinds_of(std::uint8_t r, std::uint8_t n);
}  // namespace returns

class PointFilter {
public:
    PointFilter();  // keeps every point

    // The filter of the CLI's options, each empty for "all": classes "2,9" or "2-5,9" (codes 0-255);
    // returns "last" or "first,single" (first, last, single, intermediate); intensity "MIN-MAX"
    // (0-65535, either side may be left out). Throws lidarscout::Error naming the option, what it
    // accepts and what it was given.
    static PointFilter parse(std::string_view classes, std::string_view returns, std::string_view intensity);

    std::bitset<256> classes;                   // codes kept
    std::uint8_t return_kinds = returns::kAny;  // a point is kept when it is one of these
    std::uint16_t intensity_min = 0, intensity_max = 65535;

    bool keeps_class(std::uint8_t code) const { return classes.test(code); }
    bool keeps_returns(std::uint8_t r, std::uint8_t n) const;
    bool keeps_intensity(std::uint16_t i) const { return i >= intensity_min && i <= intensity_max; }
    // Only what the point knows is checked: an overview point without returns passes on returns.
    bool keeps(std::uint8_t code, std::uint8_t r, std::uint8_t n, std::uint16_t intensity) const {
        return keeps_class(code) && keeps_returns(r, n) && keeps_intensity(intensity);
    }
    bool keeps(const las::Point& p) const;
    // A point whose return kinds (returns::kinds_of) are known.
    bool keeps_kinds(std::uint8_t code, std::uint8_t kinds, std::uint16_t intensity) const {
        return keeps_class(code) && (keeps_every_return() || (kinds & return_kinds) != 0) && keeps_intensity(intensity);
    }

    bool keeps_every_class() const { return classes.all(); }
    bool keeps_every_return() const { return return_kinds == returns::kAny; }
    bool keeps_everything() const;
    bool operator==(const PointFilter&) const = default;

    // "classes 2,9; last returns; intensity 10-200", or "all points".
    std::string describe() const;
    // The classes kept as the CLI writes them ("2-5,9"); empty when every class is kept.
    std::string class_list() const;
};

// The viewer's presets, in menu order.
struct FilterPreset {
    std::string_view name;
    PointFilter filter;
};
std::span<const FilterPreset> filter_presets();

// Points counted by class and by return kind (a point counts once per kind it is).
struct PointCounts {
    std::array<std::uint64_t, 256> by_class{};
    std::uint64_t first = 0, last = 0, single = 0, intermediate = 0, total = 0;

    void add(std::uint8_t code, std::uint8_t r, std::uint8_t n);
    void add(const las::Point& p);
    PointCounts& operator+=(const PointCounts& o);
};

}  // namespace lidarscout::dataset
