// Relief: river geometry (a sine meander plus noise), the valley profile around it (bed,
// banks, flood plain, valley sides) and the hills (domain-warped fractal noise plus ridged
// noise plus small undulations).
#include "synth/relief.hpp"

#include <algorithm>

#include "core/random.hpp"
#include "synth/noise.hpp"

namespace lidarscout::synth {
namespace {

constexpr double kTwoPi = 6.283185307179586;

// Stream ids: each noise field gets its own seed.
enum Stream : std::uint64_t { kMeander = 1, kWidth, kWarpX, kWarpY, kLarge, kRidge, kDetail, kPhase, kLevel };

// A smooth max(v, 0) with a rounding of about `r` metres.
double soft_positive(double v, double r) { return 0.5 * (v + std::sqrt(v * v + r * r)); }

// Height of the valley floor above the water level at distance d from the centre line.
double valley_floor(double d, double half_width) {
    if (d < half_width) {
        const double t = 1 - d / half_width;
        return -1.2 - 1.3 * t * t;  // river bed
    }
    const double bank = smoothstep(half_width, half_width + 6, d);
    return -1.2 + 3.0 * bank + 0.004 * std::max(0.0, d - half_width - 6);
}

}  // namespace

Relief::Relief(std::uint64_t seed, const Area& area) : seed_(seed), area_(area) {
    const double w = area.size();
    meander_amplitude_ = std::min(0.07 * w, 110.0);
    meander_wavelength_ = 1100.0;
    meander_phase_ = kTwoPi * unit_of(hash_of(seed, kPhase));
    wobble_amplitude_ = std::min(0.04 * w, 45.0);
    valley_width_ = std::min(0.35 * w, 600.0);
    base_level_ = 360.0 + 60.0 * unit_of(hash_of(seed, kLevel));
}

double Relief::river_centre(double y) const {
    const double v = y - area_.y0;
    return area_.x0 + 0.38 * area_.size() +
           meander_amplitude_ * std::sin(kTwoPi * v / meander_wavelength_ + meander_phase_) +
           wobble_amplitude_ * fractal_noise_1d(hash_of(seed_, kMeander), v / 400.0, 3);
}

RiverRow Relief::river(double y) const {
    RiverRow r;
    r.centre = river_centre(y);
    const double slope = (river_centre(y + 0.5) - river_centre(y - 0.5));
    r.cos_slope = 1.0 / std::sqrt(1.0 + slope * slope);
    r.half_width = 9.0 + 3.0 * fractal_noise_1d(hash_of(seed_, kWidth), (y - area_.y0) / 500.0, 2);
    r.water_level = base_level_ + 0.0015 * (y - area_.y0);  // flows south
    return r;
}

double Relief::hills(double x, double y) const {
    const double u = x - area_.x0, v = y - area_.y0;
    const double wx = u + 130.0 * fractal_noise(hash_of(seed_, kWarpX), u / 1600.0, v / 1600.0, 3);
    const double wy = v + 130.0 * fractal_noise(hash_of(seed_, kWarpY), u / 1600.0, v / 1600.0, 3);
    const double large = fractal_noise(hash_of(seed_, kLarge), wx / 2600.0, wy / 2600.0, 4);
    const double ridge = ridged_noise(hash_of(seed_, kRidge), wx / 1300.0, wy / 1300.0, 4);
    return soft_positive(55.0 + 150.0 * large + 130.0 * (ridge - 0.35), 16.0);
}

double Relief::ground(double x, double y, const RiverRow& river) const {
    const double d = river.distance(x);
    const double valley = smoothstep(river.half_width + 30, river.half_width + 30 + valley_width_, d);
    const double u = x - area_.x0, v = y - area_.y0;
    const double detail = fractal_noise(hash_of(seed_, kDetail), u / 140.0, v / 140.0, 3);
    const double roughness = 0.4 + 2.6 * valley;
    const double floor = valley_floor(d, river.half_width);
    return river.water_level + floor + (valley > 0 ? valley * hills(x, y) : 0.0) +
           (d > river.half_width + 8 ? roughness * detail * smoothstep(river.half_width + 8, river.half_width + 40, d)
                                     : 0.0);
}

}  // namespace lidarscout::synth
