// Patch detail from full-resolution points: per-texel sums per tile, merged means, the overlay.
#include "viewer/patch_detail.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "render/framebuffer.hpp"

namespace lidarscout::viewer {
namespace {

// One tile's sums over one patch.
struct TexelSums {
    std::vector<double> z, r, g, b;
    std::vector<std::uint32_t> n;
    explicit TexelSums(int size) {
        const std::size_t t = static_cast<std::size_t>(size) * size;
        z.assign(t, 0), r.assign(t, 0), g.assign(t, 0), b.assign(t, 0), n.assign(t, 0);
    }
};

PatchDetail empty_detail(const lidarscout::PatchGrid& grid, lidarscout::CellKey cell, int size) {
    PatchDetail d;
    d.origin_x = grid.cell_min_x(cell), d.origin_y = grid.cell_min_y(cell);
    d.texel_m = grid.patch_size() / size;
    d.size = size;
    const std::size_t t = static_cast<std::size_t>(size) * size;
    d.height.assign(t, std::numeric_limits<float>::quiet_NaN());
    d.count.assign(t, 0);
    d.colour.assign(t, 0);
    return d;
}

std::uint8_t channel_mean(double a, std::uint32_t na, double b, std::uint32_t nb) {
    return static_cast<std::uint8_t>(std::lround((a * na + b * nb) / (na + nb)));
}

PatchDetail detail_from_sums(const PatchGrid& grid, CellKey cell, int size, const TexelSums& s) {
    PatchDetail d = empty_detail(grid, cell, size);
    for (std::size_t t = 0; t < s.n.size(); ++t) {
        const std::uint32_t n = s.n[t];
        if (n == 0) continue;
        d.height[t] = static_cast<float>(s.z[t] / n);
        d.colour[t] = render::pack_rgba(channel_mean(s.r[t] / n, n, 0, 0), channel_mean(s.g[t] / n, n, 0, 0),
                                        channel_mean(s.b[t] / n, n, 0, 0));
        d.count[t] = n;
    }
    return d;
}

}  // namespace

PatchDetails tile_detail(const PointSet& set, const lidarscout::PatchGrid& grid, int size) {
    std::map<lidarscout::CellKey, TexelSums> sums;
    const double texel = grid.patch_size() / size;
    TexelSums* s = nullptr;  // the last point's cell (points come in scan order: few switches)
    lidarscout::CellKey last{};
    for (const auto& p : set.points) {
        const double x = set.origin_x + p.dx, y = set.origin_y + p.dy;
        const lidarscout::CellKey cell = grid.cell_of(x, y);
        const int col = std::clamp(static_cast<int>((x - grid.cell_min_x(cell)) / texel), 0, size - 1);
        const int row = std::clamp(static_cast<int>((y - grid.cell_min_y(cell)) / texel), 0, size - 1);
        if (!s || !(cell == last)) {
            s = &sums.try_emplace(cell, size).first->second;
            last = cell;
        }
        const std::size_t t = static_cast<std::size_t>(row) * size + col;
        s->z[t] += set.origin_z + p.dz, s->r[t] += p.r, s->g[t] += p.g, s->b[t] += p.b;
        ++s->n[t];
    }
    PatchDetails out;
    for (const auto& [cell, s] : sums) out.emplace(cell, detail_from_sums(grid, cell, size, s));
    return out;
}

void merge_detail(PatchDetail& into, const PatchDetail& from) {
    for (std::size_t t = 0; t < into.count.size() && t < from.count.size(); ++t) {
        const std::uint32_t a = into.count[t], b = from.count[t];
        if (b == 0) continue;
        if (a == 0) {
            into.height[t] = from.height[t], into.colour[t] = from.colour[t], into.count[t] = b;
            continue;
        }
        into.height[t] = static_cast<float>((double{into.height[t]} * a + double{from.height[t]} * b) / (a + b));
        const std::uint32_t p = into.colour[t], q = from.colour[t];
        into.colour[t] = render::pack_rgba(channel_mean(render::red(p), a, render::red(q), b),
                                           channel_mean(render::green(p), a, render::green(q), b),
                                           channel_mean(render::blue(p), a, render::blue(q), b));
        into.count[t] = a + b;
    }
}

PatchHeightmap overlay_detail(const PatchHeightmap& base, const PatchDetail& detail) {
    PatchHeightmap out = base;
    out.cache_key = 0;  // other heights than the base's: share() gives it a key of its own
    if (detail.size != base.size) return out;
    for (std::size_t t = 0; t < out.heights.size(); ++t) {
        if (detail.count[t] == 0) continue;
        out.heights[t] = detail.height[t];
        if (!out.colours.empty()) out.colours[t] = detail.colour[t];
    }
    return out;
}

void overlay_points(std::vector<PatchHeightmap>& heightmaps, std::span<const PointSet> sets,
                    const lidarscout::PatchGrid& grid) {
    if (heightmaps.empty()) return;
    PatchDetails merged;
    for (const auto& set : sets) {
        for (auto& [cell, d] : tile_detail(set, grid, heightmaps.front().size)) {
            const auto [it, added] = merged.try_emplace(cell, std::move(d));
            if (!added) merge_detail(it->second, d);
        }
    }
    for (auto& h : heightmaps) {
        if (const auto it = merged.find(h.cell); it != merged.end()) h = overlay_detail(h, it->second);
    }
}

}  // namespace lidarscout::viewer
