// Quantizing chunk points and heightmaps into the API's binary forms.
#include "serve/encoding.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

namespace lidarscout::serve {
namespace {

template <typename T>
void put(std::string& out, T value) {
    char bytes[sizeof(T)];
    std::memcpy(bytes, &value, sizeof(T));  // little-endian hosts only (x86-64, aarch64)
    out.append(bytes, sizeof(T));
}

// value in [lo, hi] -> [0, steps - 1], rounded to the nearest step.
std::uint32_t quantize(double value, double lo, double hi, std::uint32_t steps) {
    const double t = hi > lo ? (value - lo) / (hi - lo) : 0.0;
    const double q = std::round(std::clamp(t, 0.0, 1.0) * (steps - 1));
    return static_cast<std::uint32_t>(q);
}

std::pair<float, float> z_range(std::span<const render::PointAttr> points) {
    float lo = std::numeric_limits<float>::infinity(), hi = -lo;
    for (const auto& p : points) lo = std::min(lo, p.dz), hi = std::max(hi, p.dz);
    return points.empty() ? std::pair{0.0f, 0.0f} : std::pair{lo, hi};
}

// The level of the point of index i (0: every 64th, ... 3: the rest).
int level_of(std::size_t i) {
    int level = kLevels - 1;
    for (std::size_t stride = 4; level > 0 && i % stride == 0; stride *= 4) --level;
    return level;
}

std::pair<float, float> height_range(const std::vector<float>& heights) {
    float lo = std::numeric_limits<float>::infinity(), hi = -lo;
    for (const float h : heights) {
        if (std::isfinite(h)) lo = std::min(lo, h), hi = std::max(hi, h);
    }
    return lo <= hi ? std::pair{lo, hi} : std::pair{0.0f, 0.0f};
}

}  // namespace

void append_block(std::string& out, std::int32_t ix, std::int32_t iy, std::span<const render::PointAttr> points,
                  double size) {
    const auto [z_min, z_max] = z_range(points);
    put<std::int32_t>(out, ix);
    put<std::int32_t>(out, iy);
    put<std::uint32_t>(out, static_cast<std::uint32_t>(points.size()));
    put<float>(out, z_min);
    put<float>(out, z_max);
    put<std::uint32_t>(out, 0);
    constexpr std::uint32_t xy_steps = 1u << kXyBits, z_steps = 1u << kZBits;
    for (const auto& p : points) {
        const std::uint32_t qx = quantize(p.dx, 0, size, xy_steps), qy = quantize(p.dy, 0, size, xy_steps);
        const std::uint32_t qz = quantize(p.dz, z_min, z_max, z_steps);
        put<std::uint32_t>(out, qx | (qy << kXyBits) | (qz << (2 * kXyBits)));
    }
    for (const auto& p : points) out.append({static_cast<char>(p.r), static_cast<char>(p.g), static_cast<char>(p.b)});
    for (const auto& p : points) out.push_back(static_cast<char>(p.classification));
    for (const auto& p : points) put<std::uint16_t>(out, p.intensity);
}

std::vector<EncodedLevel> encode_levels(const viewer::PointSet& set, double origin_x, double origin_y) {
    // blocks of kLodBlockM over the tile's extent, each point moved to its block's corner
    float extent_x = 0, extent_y = 0;
    for (const auto& p : set.points) extent_x = std::max(extent_x, p.dx), extent_y = std::max(extent_y, p.dy);
    const int nx = static_cast<int>(extent_x / kLodBlockM) + 1, ny = static_cast<int>(extent_y / kLodBlockM) + 1;
    std::vector<std::vector<std::vector<render::PointAttr>>> blocks(
        kLevels, std::vector<std::vector<render::PointAttr>>(static_cast<std::size_t>(nx) * ny));
    for (std::size_t i = 0; i < set.points.size(); ++i) {
        render::PointAttr p = set.points[i];
        const int bx = std::clamp(static_cast<int>(p.dx / kLodBlockM), 0, nx - 1);
        const int by = std::clamp(static_cast<int>(p.dy / kLodBlockM), 0, ny - 1);
        p.dx -= static_cast<float>(bx * kLodBlockM), p.dy -= static_cast<float>(by * kLodBlockM);
        blocks[level_of(i)][static_cast<std::size_t>(by) * nx + bx].push_back(p);
    }
    std::vector<EncodedLevel> out(kLevels);
    for (int level = 0; level < kLevels; ++level) {
        auto& e = out[level];
        const double spacing = set.spacing_m * std::sqrt(std::pow(4.0, kLevels - 1 - level));
        std::uint32_t used = 0;
        for (const auto& b : blocks[level]) used += !b.empty();
        for (const double v : {set.origin_x - origin_x, set.origin_y - origin_y, set.origin_z, kLodBlockM, spacing}) {
            put<float>(e.body, static_cast<float>(v));
        }
        put<std::uint32_t>(e.body, static_cast<std::uint32_t>(level));
        put<std::uint32_t>(e.body, used);
        put<std::uint32_t>(e.body, 0);
        for (int by = 0; by < ny; ++by) {
            for (int bx = 0; bx < nx; ++bx) {
                const auto& b = blocks[level][static_cast<std::size_t>(by) * nx + bx];
                if (!b.empty()) append_block(e.body, bx, by, b, kLodBlockM);
                e.points += b.size();
            }
        }
    }
    return out;
}

DecodedPosition decode_position(std::uint32_t packed, double patch_size, float z_min, float z_max) {
    constexpr std::uint32_t xy_mask = (1u << kXyBits) - 1, z_mask = (1u << kZBits) - 1;
    const double xy_step = patch_size / (xy_mask), z_step = (z_max - z_min) / static_cast<double>(z_mask);
    return {(packed & xy_mask) * xy_step, ((packed >> kXyBits) & xy_mask) * xy_step,
            z_min + ((packed >> (2 * kXyBits)) & z_mask) * z_step};
}

void append_heightmap(std::string& out, const viewer::PatchHeightmap& h, double origin_x, double origin_y) {
    const auto [z_min, z_max] = height_range(h.heights);
    const bool colours = h.colours.size() == h.heights.size();
    put<std::int32_t>(out, h.cell.ix);
    put<std::int32_t>(out, h.cell.iy);
    put<std::uint16_t>(out, static_cast<std::uint16_t>(h.size));
    put<std::uint16_t>(out, colours ? 1 : 0);
    put<float>(out, static_cast<float>(h.origin_x - origin_x));
    put<float>(out, static_cast<float>(h.origin_y - origin_y));
    put<float>(out, static_cast<float>(h.texel_m));
    put<float>(out, z_min);
    put<float>(out, z_max);
    for (const float z : h.heights) {
        put<std::uint16_t>(out, std::isfinite(z) ? static_cast<std::uint16_t>(quantize(z, z_min, z_max, 65535))
                                                 : kNoHeight);
    }
    if (!colours) return;
    for (const std::uint32_t c : h.colours) {  // rgba8, red in the low byte
        out.append({static_cast<char>(c & 0xff), static_cast<char>((c >> 8) & 0xff),
                    static_cast<char>((c >> 16) & 0xff)});
    }
}

}  // namespace lidarscout::serve
