// How a point or heightmap texel becomes a colour: its own RGB, a ramp over elevation, a grey
// ramp over intensity, or the ASPRS class colours. The passes build a Palette once per frame
// (lookup tables) and then colour every point with a table lookup, no per-point branching on
// the mode inside the loops.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string_view>

#include "render/point_batch.hpp"

namespace lidarscout::render {

enum class ColourMode { Rgb, Elevation, Intensity, Classification };

// "rgb", "elevation", "intensity", "classification"; throws lidarscout::Error naming the
// known modes otherwise.
ColourMode parse_colour_mode(std::string_view name);
std::string_view colour_mode_name(ColourMode mode);

struct ColourSettings {
    ColourMode mode = ColourMode::Rgb;
    double z_min = 0, z_max = 1000;  // elevation ramp range, world metres
    float intensity_min = 0, intensity_max = 65535;
    float intensity_gamma = 1.0f;  // grey = t^(1/gamma): > 1 brightens the dark end
};

// The elevation ramp at t in [0, 1] (clamped): indigo, blue, teal, green, yellow, light orange,
// near white, with monotonic lightness. Our own stops, interpolated linearly.
std::uint32_t elevation_ramp(float t);
// ASPRS standard classes 0-22 (LAS 1.4 R15); other values get a distinct hashed hue.
std::uint32_t classification_colour(std::uint8_t cls);

// The 2nd and 98th percentiles of the intensities of `batches` (a robust auto range for
// ColourSettings::intensity_min/max); {0, 65535} when there are no points.
std::array<float, 2> auto_intensity_range(std::span<const PointBatch> batches);

// Lookup tables for one frame's ColourSettings.
class Palette {
public:
    static constexpr int kRampSize = 1024;

    explicit Palette(const ColourSettings& settings);
    ColourMode mode() const { return mode_; }

    // Elevation colour for heights stored as offsets from origin_z (float arithmetic only).
    struct ElevationMap {
        const std::uint32_t* lut;
        float offset, scale;  // ramp index = (dz + offset) * scale
        std::uint32_t operator()(float dz) const {
            float i = (dz + offset) * scale;
            if (!(i >= 0.0f)) i = 0.0f;
            if (i > kRampSize - 1) i = kRampSize - 1;
            return lut[static_cast<int>(i)];
        }
    };
    ElevationMap elevation_map(double origin_z) const;

    std::uint32_t intensity(std::uint16_t value) const {
        float i = (static_cast<float>(value) - intensity_min_) * intensity_scale_;
        if (!(i >= 0.0f)) i = 0.0f;
        if (i > kRampSize - 1) i = kRampSize - 1;
        return grey_[static_cast<int>(i)];
    }
    std::uint32_t classification(std::uint8_t cls) const { return classes_[cls]; }

private:
    ColourMode mode_;
    double z_min_;
    float z_scale_;
    float intensity_min_, intensity_scale_;
    std::array<std::uint32_t, kRampSize> ramp_{}, grey_{};
    std::array<std::uint32_t, 256> classes_{};
};

}  // namespace lidarscout::render
