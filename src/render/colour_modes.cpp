// Colour modes: the elevation ramp, the ASPRS class colours, the intensity grey ramp and the
// per-frame lookup tables.
#include "render/colour_modes.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>

#include "core/error.hpp"
#include "core/named_values.hpp"
#include "render/framebuffer.hpp"

namespace lidarscout::render {
namespace {

struct Stop {
    float t;
    std::uint8_t r, g, b;
};

// Our own ramp: dark and cool at the bottom, warm and light at the top, its lightness rising
// monotonically so that relief also reads in grey and for colour-blind viewers.
constexpr std::array<Stop, 8> kElevationStops = {{
    {0.00f, 40, 30, 100},
    {0.15f, 35, 85, 170},
    {0.30f, 25, 140, 160},
    {0.45f, 80, 175, 90},
    {0.60f, 175, 195, 70},
    {0.75f, 235, 190, 70},
    {0.90f, 245, 205, 150},
    {1.00f, 255, 245, 235},
}};

struct NamedClass {
    std::uint8_t r, g, b;
};

// ASPRS LAS 1.4 R15 standard classes 0-22.
constexpr std::array<NamedClass, 23> kClassColours = {{
    {150, 150, 150},  // 0 created, never classified
    {200, 200, 200},  // 1 unclassified
    {150, 110, 70},   // 2 ground
    {160, 210, 110},  // 3 low vegetation
    {80, 165, 60},    // 4 medium vegetation
    {25, 105, 40},    // 5 high vegetation
    {220, 80, 50},    // 6 building
    {255, 0, 255},    // 7 low point (noise)
    {255, 215, 0},    // 8 reserved (model key point in LAS 1.2)
    {40, 110, 220},   // 9 water
    {120, 80, 120},   // 10 rail
    {90, 90, 100},    // 11 road surface
    {230, 230, 130},  // 12 reserved (overlap in LAS 1.2)
    {250, 250, 190},  // 13 wire - guard (shield)
    {255, 240, 100},  // 14 wire - conductor (phase)
    {200, 150, 255},  // 15 transmission tower
    {230, 200, 255},  // 16 wire-structure connector
    {185, 140, 205},  // 17 bridge deck
    {255, 60, 180},   // 18 high noise
    {255, 150, 80},   // 19 overhead structure
    {175, 145, 115},  // 20 ignored ground
    {240, 250, 255},  // 21 snow
    {120, 120, 165},  // 22 temporal exclusion
}};

constexpr std::array<std::string_view, 4> kModeNames = {"rgb", "elevation", "intensity", "classification"};

std::uint8_t to_byte(float v) { return static_cast<std::uint8_t>(std::clamp(v, 0.0f, 255.0f) + 0.5f); }

// Hue in [0, 1) at full saturation and 85% value, for classes without a standard colour.
std::uint32_t hue_colour(float hue) {
    const float h = 6.0f * (hue - std::floor(hue));
    const int sector = static_cast<int>(h) % 6;
    const float f = h - std::floor(h), v = 0.85f * 255.0f;
    const float rising = v * f, falling = v * (1.0f - f);
    const std::array<std::array<float, 3>, 6> rgb = {{
        {v, rising, 0}, {falling, v, 0}, {0, v, rising}, {0, falling, v}, {rising, 0, v}, {v, 0, falling},
    }};
    return pack_rgba(to_byte(rgb[sector][0]), to_byte(rgb[sector][1]), to_byte(rgb[sector][2]));
}

void check_settings(const ColourSettings& s) {
    if (!(s.z_max > s.z_min) || !std::isfinite(s.z_min) || !std::isfinite(s.z_max)) {
        throw Error("colour settings: the elevation range needs z_min < z_max");
    }
    if (!(s.intensity_max > s.intensity_min)) {
        throw Error("colour settings: the intensity range needs intensity_min < intensity_max");
    }
    if (!(s.intensity_gamma > 0.0f) || !std::isfinite(s.intensity_gamma)) {
        throw Error("colour settings: the intensity gamma must be positive");
    }
}

float percentile_of(const std::array<std::uint64_t, 65536>& histogram, std::uint64_t total, double fraction) {
    const auto target = static_cast<std::uint64_t>(fraction * static_cast<double>(total - 1));
    std::uint64_t seen = 0;
    for (std::size_t v = 0; v < histogram.size(); ++v) {
        seen += histogram[v];
        if (seen > target) return static_cast<float>(v);
    }
    return 65535.0f;
}

}  // namespace

ColourMode parse_colour_mode(std::string_view name) { return parse_named<ColourMode>(kModeNames, name, "colour mode"); }

std::string_view colour_mode_name(ColourMode mode) { return name_of(kModeNames, mode); }

std::uint32_t elevation_ramp(float t) {
    if (!(t > 0.0f)) t = 0.0f;
    t = std::min(t, 1.0f);
    std::size_t i = 1;
    while (i + 1 < kElevationStops.size() && kElevationStops[i].t < t) ++i;
    const Stop& a = kElevationStops[i - 1];
    const Stop& b = kElevationStops[i];
    const float f = (t - a.t) / (b.t - a.t);
    const auto mix = [f](std::uint8_t x, std::uint8_t y) { return to_byte(x + f * (static_cast<float>(y) - x)); };
    return pack_rgba(mix(a.r, b.r), mix(a.g, b.g), mix(a.b, b.b));
}

std::uint32_t classification_colour(std::uint8_t cls) {
    if (cls < kClassColours.size()) {
        const NamedClass& c = kClassColours[cls];
        return pack_rgba(c.r, c.g, c.b);
    }
    return hue_colour(0.61803398875f * cls);  // golden-ratio steps keep neighbours apart
}

std::array<float, 2> auto_intensity_range(std::span<const PointBatch> batches) {
    auto histogram = std::make_unique<std::array<std::uint64_t, 65536>>();
    histogram->fill(0);
    std::uint64_t total = 0;
    for (const PointBatch& batch : batches) {
        for (const PointAttr& p : batch.points) ++(*histogram)[p.intensity];
        total += batch.points.size();
    }
    if (total == 0) return {0.0f, 65535.0f};
    const float lo = percentile_of(*histogram, total, 0.02), hi = percentile_of(*histogram, total, 0.98);
    return {lo, std::max(hi, lo + 1.0f)};
}

Palette::Palette(const ColourSettings& settings) : mode_(settings.mode), z_min_(settings.z_min) {
    check_settings(settings);
    z_scale_ = static_cast<float>(kRampSize / (settings.z_max - settings.z_min));
    intensity_min_ = settings.intensity_min;
    intensity_scale_ = kRampSize / (settings.intensity_max - settings.intensity_min);
    for (int k = 0; k < kRampSize; ++k) {
        const float t = (k + 0.5f) / kRampSize;
        ramp_[k] = elevation_ramp(t);
        const std::uint8_t grey = to_byte(255.0f * std::pow(t, 1.0f / settings.intensity_gamma));
        grey_[k] = pack_rgba(grey, grey, grey);
    }
    for (int c = 0; c < 256; ++c) classes_[c] = classification_colour(static_cast<std::uint8_t>(c));
}

Palette::ElevationMap Palette::elevation_map(double origin_z) const {
    return {ramp_.data(), static_cast<float>(origin_z - z_min_), z_scale_};
}

}  // namespace lidarscout::render
