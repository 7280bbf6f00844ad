// What the surfaces of the synthetic landscape are made of: a colour as an orthophoto would
// show it (sRGB, 0-1) and a reflectance at the laser's wavelength (1064 nm, 0-1), which
// drives the intensity of returns. Vegetation is bright in the near infrared, asphalt and
// water are dark.
#pragma once

#include <cstdint>

namespace lidarscout::synth {

enum class Material : std::uint8_t {
    Water, Bank, Meadow, Wheat, Soil, YoungCrop, Rapeseed, Maize, ForestFloor, Lawn,
    Asphalt, Marking, Concrete, RoofTile, RoofBrown, RoofSlate, RoofFlat, Leaves, Needles,
};

struct Rgb {
    double r = 0, g = 0, b = 0;
};

Rgb base_colour(Material m);
double reflectance(Material m);

// colour * factor, per channel.
inline Rgb scaled(Rgb c, double f) { return {c.r * f, c.g * f, c.b * f}; }
inline Rgb mixed(Rgb a, Rgb b, double t) {
    return {a.r + (b.r - a.r) * t, a.g + (b.g - a.g) * t, a.b + (b.b - a.b) * t};
}

}  // namespace lidarscout::synth
