// plan_flight: strip layout centred on the area, per-strip pulse density from how much of
// the area the swaths cover, and the timing of strips, lines and pulses.
#include "synth/flight_plan.hpp"

#include <algorithm>
#include <cmath>

#include "core/random.hpp"
#include "synth/noise.hpp"

namespace lidarscout::synth {
namespace {

enum Stream : std::uint64_t { kDrift = 601 };

// 2023-06-14 08:00 UTC as adjusted standard GPS time (GPS seconds minus 1e9).
constexpr double kSurveyStart = 370'764'818.0;

}  // namespace

double FlightPlan::centre(std::uint32_t k) const {
    return area.x0 + 0.5 * area.size() + (k - 0.5 * (strips - 1.0)) * strip_spacing;
}

double FlightPlan::start_y(std::uint32_t k) const {
    return direction(k) > 0 ? area.y0 - run_in : area.y1() + run_in;
}

double FlightPlan::strip_time(std::uint32_t k) const {
    const double strip_seconds = lines_per_strip * line_spacing / speed;
    return start_time + k * (strip_seconds + turn_time);
}

double FlightPlan::drift(std::uint32_t k, std::uint32_t j) const {
    return 4.0 * fractal_noise_1d(hash_of(seed, kDrift, k), j * line_spacing / 450.0, 2);
}

FlightPlan plan_flight(std::uint64_t seed, const Area& area, double pulses_per_m2) {
    FlightPlan p;
    p.seed = seed;
    p.area = area;
    p.start_time = kSurveyStart;
    const double w = area.size();
    p.strips = static_cast<std::uint32_t>(std::ceil(w / p.strip_spacing));
    // How much of the area the swaths cover, counting overlaps twice.
    double covered = 0;
    for (std::uint32_t k = 0; k < p.strips; ++k) {
        const double lo = std::max(area.x0, p.centre(k) - p.half_swath),
                     hi = std::min(area.x1(), p.centre(k) + p.half_swath);
        covered += std::max(0.0, hi - lo);
    }
    const double strip_density = pulses_per_m2 * w / covered;
    const double spacing = 1.0 / std::sqrt(strip_density);
    p.pulses_per_line = std::max<std::uint32_t>(1, static_cast<std::uint32_t>(std::lround(2 * p.half_swath / spacing)));
    p.pulse_spacing = 2 * p.half_swath / p.pulses_per_line;
    p.line_spacing = 1.0 / (strip_density * p.pulse_spacing);
    p.lines_per_strip = static_cast<std::uint32_t>(std::ceil((w + 2 * p.run_in) / p.line_spacing));
    return p;
}

}  // namespace lidarscout::synth
