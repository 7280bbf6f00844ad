// Patch detail from full-resolution points: per-texel sums per tile (every point, ground and water
// apart), merged means, the overlay (bare earth with its holes filled by pull-push).
#include "viewer/patch_detail.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <optional>

#include "recon/hole_fill.hpp"
#include "render/framebuffer.hpp"

namespace lidarscout::viewer {
namespace {

constexpr std::uint8_t kGroundClass = 2, kWaterClass = 9;

// One tile's sums over one patch, for one layer.
struct TexelSums {
    std::vector<double> z, r, g, b;
    std::vector<std::uint32_t> n;
    explicit TexelSums(int size) {
        const std::size_t t = static_cast<std::size_t>(size) * size;
        z.assign(t, 0), r.assign(t, 0), g.assign(t, 0), b.assign(t, 0), n.assign(t, 0);
    }
    void add(std::size_t t, double height, const render::PointAttr& p) {
        z[t] += height, r[t] += p.r, g[t] += p.g, b[t] += p.b;
        ++n[t];
    }
};

// The sums of every point of one patch, and of its ground and water points (made when met).
struct PatchSums {
    int size;
    TexelSums all;
    std::optional<TexelSums> ground, water;
    explicit PatchSums(int s) : size(s), all(s) {}
    void add(std::size_t t, double height, const render::PointAttr& p) {
        all.add(t, height, p);
        if (p.classification == kGroundClass) (ground ? *ground : ground.emplace(size)).add(t, height, p);
        if (p.classification == kWaterClass) (water ? *water : water.emplace(size)).add(t, height, p);
    }
};

DetailLayer empty_layer(int size) {
    const std::size_t t = static_cast<std::size_t>(size) * size;
    DetailLayer l;
    l.height.assign(t, std::numeric_limits<float>::quiet_NaN());
    l.count.assign(t, 0);
    l.colour.assign(t, 0);
    return l;
}

std::uint8_t channel_mean(double a, std::uint32_t na, double b, std::uint32_t nb) {
    return static_cast<std::uint8_t>(std::lround((a * na + b * nb) / (na + nb)));
}

DetailLayer layer_from_sums(int size, const TexelSums& s) {
    DetailLayer d = empty_layer(size);
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

PatchDetail detail_from_sums(const PatchGrid& grid, CellKey cell, const PatchSums& s) {
    PatchDetail d;
    d.origin_x = grid.cell_min_x(cell), d.origin_y = grid.cell_min_y(cell);
    d.texel_m = grid.patch_size() / s.size;
    d.size = s.size;
    d.all = layer_from_sums(s.size, s.all);
    if (s.ground) d.ground = layer_from_sums(s.size, *s.ground);
    if (s.water) d.water = layer_from_sums(s.size, *s.water);
    return d;
}

// Per texel the count-weighted mean of `into` and `from` (same size); an empty `from` adds nothing.
void merge_layer(DetailLayer& into, const DetailLayer& from) {
    if (from.empty()) return;
    if (into.empty()) {
        into = from;
        return;
    }
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

// The layer a surface shows (ground and water merged into `merged`); null for Surface::All.
const DetailLayer* surface_layer(const PatchDetail& detail, Surface surface, DetailLayer& merged) {
    switch (surface) {
        case Surface::Ground: return &detail.ground;
        case Surface::Water: return &detail.water;
        case Surface::GroundAndWater:
            merged = detail.ground;
            merge_layer(merged, detail.water);
            return &merged;
        case Surface::All: break;
    }
    return nullptr;
}

}  // namespace

PatchDetails tile_detail(const PointSet& set, const lidarscout::PatchGrid& grid, int size) {
    std::map<lidarscout::CellKey, PatchSums> sums;
    const double texel = grid.patch_size() / size;
    PatchSums* s = nullptr;  // the last point's cell (points come in scan order: few switches)
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
        s->add(static_cast<std::size_t>(row) * size + col, set.origin_z + p.dz, p);
    }
    PatchDetails out;
    for (const auto& [cell, s] : sums) out.emplace(cell, detail_from_sums(grid, cell, s));
    return out;
}

void merge_detail(PatchDetail& into, const PatchDetail& from) {
    merge_layer(into.all, from.all);
    merge_layer(into.ground, from.ground);
    merge_layer(into.water, from.water);
}

PatchHeightmap overlay_detail(const PatchHeightmap& base, const PatchDetail& detail, Surface surface) {
    PatchHeightmap out = base;
    out.cache_key = 0;  // other heights than the base's: share() gives it a key of its own
    out.surface = surface;
    const bool read = detail.size == base.size && !detail.all.empty();  // full-resolution points fell here
    DetailLayer merged;
    const DetailLayer* layer = read ? surface_layer(detail, surface, merged) : nullptr;
    if (surface == Surface::All) {
        if (!read) return out;
        for (std::size_t t = 0; t < out.heights.size(); ++t) {
            if (detail.all.count[t] == 0) continue;
            out.heights[t] = detail.all.height[t];
            if (!out.colours.empty()) out.colours[t] = detail.all.colour[t];
        }
        return out;
    }
    const bool textured = !out.colours.empty();
    if (!textured) out.colours.assign(out.heights.size(), kNoColourGrey);
    std::vector<float> bare(out.heights.size(), std::numeric_limits<float>::quiet_NaN());
    std::vector<bool> holes(out.heights.size(), false);  // read, but none of the surface's points fell there
    for (std::size_t t = 0; read && t < bare.size(); ++t) {
        if (!layer->empty() && layer->count[t] > 0) {
            bare[t] = layer->height[t];
            if (textured) out.colours[t] = layer->colour[t];
        } else {
            holes[t] = detail.all.count[t] > 0;
        }
    }
    recon::hole_fill(bare, out.size, holes);
    for (std::size_t t = 0; t < bare.size(); ++t) {
        if (!std::isnan(bare[t])) {
            out.heights[t] = bare[t];
            continue;
        }
        const std::uint32_t c = out.colours[t];  // the overview stands here: marked to be tinted
        out.colours[t] = render::pack_rgba(render::red(c), render::green(c), render::blue(c), kOverviewAlpha);
    }
    return out;
}

void overlay_points(std::vector<PatchHeightmap>& heightmaps, std::span<const PointSet> sets,
                    const lidarscout::PatchGrid& grid, Surface surface) {
    if (heightmaps.empty()) return;
    PatchDetails merged;
    for (const auto& set : sets) {
        for (auto& [cell, d] : tile_detail(set, grid, heightmaps.front().size)) {
            const auto [it, added] = merged.try_emplace(cell, std::move(d));
            if (!added) merge_detail(it->second, d);
        }
    }
    for (auto& h : heightmaps) {
        if (const auto it = merged.find(h.cell); it != merged.end()) h = overlay_detail(h, it->second, surface);
    }
}

}  // namespace lidarscout::viewer
