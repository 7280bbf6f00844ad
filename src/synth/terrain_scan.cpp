// scan_tile: walks the flight plan's pulses that can land in the tile (strip by strip, line
// by line, pulse by pulse), keeps those whose quantised position falls in the tile, and turns
// each into its returns with the tile's TerrainPatch.
#include "synth/terrain_scan.hpp"

#include <algorithm>
#include <cmath>

#include "core/random.hpp"
#include "synth/terrain_patch.hpp"

namespace lidarscout::synth {
namespace {

enum Stream : std::uint64_t { kPulse = 701, kGain };

constexpr double kDegrees = 57.29577951308232;
constexpr double kPatchMargin = 2.0;    // metres around the tile the patch also covers
constexpr double kPositionNoise = 0.03; // metres (GNSS/IMU), bounded by ~3.5 of these
constexpr double kRangeNoise = 0.02;    // metres

struct Return {
    double z = 0;
    std::uint8_t cls = 0;
    double reflectance = 0;
};

struct Returns {
    std::array<Return, 3> r;
    int n = 0;
    void add(double z, std::uint8_t cls, double reflectance) { r[n++] = {z, cls, reflectance}; }
};

std::uint8_t vegetation_class(double height) {
    return height < 2.0 ? cls::kLowVegetation : height < 5.0 ? cls::kMediumVegetation : cls::kHighVegetation;
}

// Water reflects the beam away except near nadir, so most pulses there give no return.
void ground_return(Returns& out, const Column& c, double angle, Rng& rng) {
    if (c.ground_class == cls::kWater && !rng.chance(std::fabs(angle) < 3.0 ? 0.9 : 0.35)) return;
    out.add(c.ground_z + kRangeNoise * rng.gaussian(), c.ground_class, reflectance(c.ground_material));
}

// Returns of a pulse through a crown: the crown's surface, perhaps a branch below, and the
// ground when the beam gets through (returns closer than ~2 m are not separated).
void canopy_returns(Returns& out, const Column& c, double angle, Rng& rng) {
    const double first = c.top_z - rng.uniform() * rng.uniform() * std::min(1.5, 0.3 * (c.top_z - c.crown_bottom));
    const double leaves = reflectance(c.top_material);
    out.add(first, vegetation_class(first - c.ground_z), leaves);
    const double room = first - c.ground_z;
    const double low = std::max(c.crown_bottom, c.ground_z + 2.0), high = first - 2.0;
    if (room > 4.5 && high > low && rng.chance(0.25)) {
        const double z = rng.uniform(low, high);
        out.add(z, vegetation_class(z - c.ground_z), leaves);
    }
    if (room > 2.0 && rng.chance(0.6)) ground_return(out, c, angle, rng);
}

Returns returns_of(const Column& c, double angle, Rng& rng) {
    Returns out;
    if (c.top == Top::Roof) {
        out.add(c.top_z + kRangeNoise * rng.gaussian(), cls::kBuilding, reflectance(c.top_material));
    } else if (c.top == Top::Canopy && rng.chance(0.97 - 0.4 * c.crown_r2)) {
        canopy_returns(out, c, angle, rng);
    } else {
        ground_return(out, c, angle, rng);
    }
    return out;
}

// The part of the pulse's energy a return gets: all of it alone, less when it is shared.
double energy(int index, int count) {
    if (count == 1) return 1.0;
    if (index == 0) return 0.55;
    return index + 1 == count ? 0.35 : 0.3;
}

std::uint16_t to_u16(double v) { return static_cast<std::uint16_t>(std::clamp(v, 0.0, 65535.0) + 0.5); }

std::int64_t quantise(double v, double offset, double scale) {
    return static_cast<std::int64_t>(std::floor((v - offset) / scale + 0.5));
}

class TileScanner {
public:
    TileScanner(const TerrainModel& model, const FlightPlan& plan, const TileRect& tile, const Quantisation& q,
                const PointSink& sink)
        : plan_(plan),
          tile_(tile),
          q_(q),
          sink_(sink),
          patch_(model, tile.x0 - kPatchMargin, tile.y0 - kPatchMargin, tile.x0 + kTileSize + kPatchMargin,
                 tile.y0 + kTileSize + kPatchMargin),
          X0_(quantise(tile.x0, q.offset[0], q.scale)),
          X1_(quantise(tile.x0 + kTileSize, q.offset[0], q.scale)),
          Y0_(quantise(tile.y0, q.offset[1], q.scale)),
          Y1_(quantise(tile.y0 + kTileSize, q.offset[1], q.scale)) {}

    void run() {
        for (std::uint32_t k = 0; k < plan_.strips; ++k) {
            const double reach = plan_.half_swath + 6.0;
            if (plan_.centre(k) + reach < tile_.x0 || plan_.centre(k) - reach > tile_.x0 + kTileSize) continue;
            scan_strip(k);
        }
    }

private:
    void scan_strip(std::uint32_t k) {
        const double dir = plan_.direction(k), sy = plan_.start_y(k), s = plan_.line_spacing;
        const double a = dir > 0 ? tile_.y0 - sy : sy - (tile_.y0 + kTileSize);
        const double b = dir > 0 ? tile_.y0 + kTileSize - sy : sy - tile_.y0;
        const double margin = 1.0 + std::ceil(0.2 / s);
        const double lo = std::max(0.0, std::floor(a / s) - margin);
        const double hi = std::min(plan_.lines_per_strip - 1.0, std::floor(b / s) + margin);
        gain_ = 0.94 + 0.12 * unit_of(hash_of(plan_.seed, kGain, k));
        for (double j = lo; j <= hi; ++j) scan_line(k, static_cast<std::uint32_t>(j));
    }

    void scan_line(std::uint32_t k, std::uint32_t j) {
        const double aircraft = plan_.centre(k) + plan_.drift(k, j);
        const double a = plan_.pulse_spacing, hw = plan_.half_swath;
        const double margin = 1.0 + std::ceil(0.2 / a);
        const bool forward = j % 2 == 0;  // even lines sweep west to east
        const double west = tile_.x0 - aircraft, east = tile_.x0 + kTileSize - aircraft;
        const double first = forward ? (west + hw) / a - 0.5 : (hw - east) / a - 0.5;
        const double last = forward ? (east + hw) / a - 0.5 : (hw - west) / a - 0.5;
        const double n = plan_.pulses_per_line;
        const double lo = std::max(0.0, std::floor(first) - margin), hi = std::min(n - 1, std::ceil(last) + margin);
        for (double i = lo; i <= hi; ++i) {
            const double across = forward ? -hw + (i + 0.5) * a : hw - (i + 0.5) * a;
            pulse(k, j, static_cast<std::uint32_t>(i), aircraft, aircraft + across);
        }
    }

    void pulse(std::uint32_t k, std::uint32_t j, std::uint32_t i, double aircraft, double x) {
        const std::uint32_t n = plan_.pulses_per_line;
        const double dir = plan_.direction(k);
        double y = plan_.start_y(k) + dir * plan_.line_spacing * (j + static_cast<double>(i) / n);
        Rng rng(hash_of(plan_.seed, kPulse, k, j, i));
        x += kPositionNoise * rng.gaussian();
        y += kPositionNoise * rng.gaussian();
        const std::int64_t X = quantise(x, q_.offset[0], q_.scale), Y = quantise(y, q_.offset[1], q_.scale);
        if (X < X0_ || X >= X1_ || Y < Y0_ || Y >= Y1_) return;

        const Column c = patch_.column(x, y);
        const double angle = std::atan((x - aircraft) * dir / plan_.altitude) * kDegrees;
        const Returns returns = returns_of(c, angle, rng);
        if (returns.n == 0) return;

        las::Point p;
        p.X = static_cast<std::int32_t>(X);
        p.Y = static_cast<std::int32_t>(Y);
        p.x = X * q_.scale + q_.offset[0];
        p.y = Y * q_.scale + q_.offset[1];
        p.number_of_returns = static_cast<std::uint8_t>(returns.n);
        p.scan_direction = forward_flag(j, dir);
        p.edge_of_flight_line = i == 0 || i + 1 == n;
        p.overlap = std::fabs(x - plan_.centre(k)) > 0.5 * plan_.strip_spacing;
        p.scan_angle_raw = static_cast<std::int16_t>(std::lround(angle / 0.006));
        p.point_source_id = static_cast<std::uint16_t>(k + 1);
        p.gps_time = plan_.strip_time(k) + (static_cast<double>(j) * n + i) * plan_.pulse_period();
        const double tint = 1.0 + 0.04 * rng.gaussian();
        p.rgb = {to_u16(c.colour.r * tint * 65535.0), to_u16(c.colour.g * tint * 65535.0),
                 to_u16(c.colour.b * tint * 65535.0)};
        const double falloff = 1.0 - 0.25 * (angle / 20.0) * (angle / 20.0);
        for (int r = 0; r < returns.n; ++r) {
            const Return& ret = returns.r[r];
            p.Z = static_cast<std::int32_t>(quantise(ret.z, q_.offset[2], q_.scale));
            p.z = p.Z * q_.scale + q_.offset[2];
            p.return_number = static_cast<std::uint8_t>(r + 1);
            p.classification = ret.cls;
            p.intensity = to_u16(ret.reflectance * energy(r, returns.n) * falloff * gain_ *
                                 (1.0 + 0.06 * rng.gaussian()) * 52000.0);
            sink_(p);
        }
    }

    // LAS scan direction flag: 1 when the mirror sweeps left to right (seen along the flight).
    static bool forward_flag(std::uint32_t j, double dir) { return (j % 2 == 0) == (dir > 0); }

    const FlightPlan& plan_;
    TileRect tile_;
    Quantisation q_;
    const PointSink& sink_;
    TerrainPatch patch_;
    std::int64_t X0_, X1_, Y0_, Y1_;
    double gain_ = 1.0;
};

}  // namespace

void scan_tile(const TerrainModel& model, const FlightPlan& plan, const TileRect& tile, const Quantisation& q,
               const PointSink& sink) {
    TileScanner(model, plan, tile, q, sink).run();
}

}  // namespace lidarscout::synth
