// Layout: the main road's curve, the valley road (an offset of the river), villages along
// the roads (the first one where the main road crosses the river valley) and farms.
#include "synth/layout.hpp"

#include <algorithm>
#include <cmath>

#include "core/random.hpp"
#include "synth/noise.hpp"

namespace lidarscout::synth {
namespace {

constexpr double kTwoPi = 6.283185307179586;
constexpr double kFarmCell = 450.0;
enum Stream : std::uint64_t { kRoadPhase = 101, kRoadNoise, kVillage, kFarm };

// A unit vector from two uniforms (close to uniformly distributed in angle).
void random_direction(Rng& rng, double& c, double& s) {
    for (int i = 0; i < 16; ++i) {
        const double a = rng.uniform(-1, 1), b = rng.uniform(-1, 1);
        const double n = std::sqrt(a * a + b * b);
        if (n > 0.2 && n <= 1.0) {
            c = a / n;
            s = b / n;
            return;
        }
    }
    c = 1;
    s = 0;
}

double distance_to_street(double t, double spacing) { return std::fabs(t - spacing * std::floor(t / spacing + 0.5)); }

}  // namespace

Layout::Layout(std::uint64_t seed, const Area& area, const Relief& relief, const LandCover& land)
    : seed_(seed), area_(area) {
    road_amplitude_ = std::min(0.05 * area.size(), 55.0);
    road_phase_ = kTwoPi * unit_of(hash_of(seed, kRoadPhase));
    place_villages(relief);
    place_farms(relief, land);
}

double Layout::main_road_centre(double x) const {
    const double u = x - area_.x0;
    return area_.y0 + 0.62 * area_.size() + road_amplitude_ * std::sin(kTwoPi * u / 1500.0 + road_phase_) +
           0.5 * road_amplitude_ * fractal_noise_1d(hash_of(seed_, kRoadNoise), u / 500.0, 2);
}

MainRoadColumn Layout::main_road(double x) const {
    MainRoadColumn c;
    c.centre = main_road_centre(x);
    const double slope = main_road_centre(x + 0.5) - main_road_centre(x - 0.5);
    c.cos_slope = 1.0 / std::sqrt(1.0 + slope * slope);
    return c;
}

void Layout::align_to_main_road(Village& v) const {
    const double slope = main_road_centre(v.x + 0.5) - main_road_centre(v.x - 0.5);
    const double n = std::sqrt(1.0 + slope * slope);
    v.cos_a = 1.0 / n;
    v.sin_a = slope / n;
    v.y = main_road_centre(v.x) + 0.5 * v.street_spacing;  // the main road runs between two streets
}

bool Layout::free_for_village(double x, double y, double radius, const Relief& relief) const {
    if (relief.river(y).distance(x) < 60.0) return false;
    for (const auto& v : villages_) {
        const double dx = x - v.x, dy = y - v.y;
        if (std::sqrt(dx * dx + dy * dy) < v.radius + radius + (v.farm ? 60.0 : 200.0)) return false;
    }
    return true;
}

void Layout::place_villages(const Relief& relief) {
    const double w = area_.size();
    Rng rng(hash_of(seed_, kVillage));
    // The first village: east of the river where the main road crosses the valley.
    {
        Village v;
        v.radius = std::min(260.0, 0.42 * w);
        v.street_spacing = rng.uniform(75, 95);
        const double guess = relief.river_centre(main_road_centre(area_.x0 + 0.4 * w)) + 230.0;
        v.x = std::clamp(guess, area_.x0 + 0.2 * w, area_.x0 + 0.85 * w);
        align_to_main_road(v);
        villages_.push_back(v);
    }
    // More villages on larger areas, along the main road or the valley road.
    const int more = static_cast<int>(w * w / 6e6);
    for (int tries = 0, placed = 0; placed < more && tries < 20 * more + 60; ++tries) {
        Village v;
        v.radius = rng.uniform(150, 240);
        v.street_spacing = rng.uniform(70, 95);
        const double t = 0.08 + 0.84 * rng.uniform();
        if (rng.chance(0.5)) {
            v.x = area_.x0 + t * w;
            align_to_main_road(v);
        } else {
            v.y = area_.y0 + t * w;
            v.x = relief.river_centre(v.y) + kValleyRoadOffset + 0.5 * v.street_spacing;
            v.cos_a = 0;
            v.sin_a = 1;
        }
        if (!free_for_village(v.x, v.y, v.radius, relief)) continue;
        villages_.push_back(v);
        ++placed;
    }
}

void Layout::place_farms(const Relief& relief, const LandCover& land) {
    const auto cells = static_cast<std::int64_t>(std::ceil(area_.size() / kFarmCell));
    for (std::int64_t j = 0; j < cells; ++j) {
        for (std::int64_t i = 0; i < cells; ++i) {
            Rng rng(hash_of(seed_, kFarm, i, j));
            if (!rng.chance(0.45)) continue;
            Village f;
            f.farm = true;
            f.radius = 45.0;
            f.x = area_.x0 + (i + rng.uniform(0.15, 0.85)) * kFarmCell;
            f.y = area_.y0 + (j + rng.uniform(0.15, 0.85)) * kFarmCell;
            random_direction(rng, f.cos_a, f.sin_a);
            const RiverRow river = relief.river(f.y);
            if (river.distance(f.x) < 90.0 || !free_for_village(f.x, f.y, f.radius, relief)) continue;
            const double height = relief.ground(f.x, f.y, river) - river.water_level;
            if (land.forest(f.x, f.y, height) > -0.08) continue;  // farms stand in the open
            villages_.push_back(f);
        }
    }
}

std::vector<const Village*> Layout::villages_near(double x0, double y0, double x1, double y1, double margin) const {
    std::vector<const Village*> out;
    for (const auto& v : villages_) {
        const double reach = v.radius + margin;
        if (v.x + reach >= x0 && v.x - reach <= x1 && v.y + reach >= y0 && v.y - reach <= y1) out.push_back(&v);
    }
    return out;
}

RoadHit Layout::road(double x, double y, const RiverRow& river, const MainRoadColumn& main,
                     const std::vector<const Village*>& villages) const {
    RoadHit best;
    const auto consider = [&](RoadKind kind, double offset, double half_width, double along) {
        if (offset - half_width < best.offset - best.half_width) best = {kind, offset, half_width, along};
    };
    consider(RoadKind::Main, std::fabs(y - main.centre) * main.cos_slope, kMainHalfWidth, x);
    consider(RoadKind::Valley, std::fabs(x - river.centre - kValleyRoadOffset) * river.cos_slope, kValleyHalfWidth, y);
    if (river.distance(x) < river.half_width + 15.0) return best;  // streets stop short of the river
    for (const Village* v : villages) {
        if (v->farm) continue;
        const double dx = x - v->x, dy = y - v->y;
        const double r2 = dx * dx + dy * dy;
        const double reach = 0.75 * v->radius;
        if (r2 > reach * reach) continue;
        const double u = dx * v->cos_a + dy * v->sin_a;
        const double w = -dx * v->sin_a + dy * v->cos_a;
        consider(RoadKind::Street, distance_to_street(w, v->street_spacing), kStreetHalfWidth, u);
        consider(RoadKind::Street, distance_to_street(u, v->street_spacing), kStreetHalfWidth, w);
    }
    return best;
}

}  // namespace lidarscout::synth
