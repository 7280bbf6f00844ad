// count_contours: crossings per texel edge, regions per level from two union-find sweeps over the
// sorted texels, and the block-by-block reading of a raster with GDAL.
#include "raster/contour_estimate.hpp"

#include <cpl_error.h>
#include <gdal_priv.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <numeric>

#include "core/error.hpp"
#include "core/radix_sort.hpp"
#include "raster/block_raster.hpp"
#include "raster/gdal_handles.hpp"

namespace lidarscout::raster {
namespace {

// Level indices of `value` for each interval: the levels below and at it (floor(value / interval)).
void level_indices(float value, std::span<const double> intervals, double* out) {
    for (std::size_t k = 0; k < intervals.size(); ++k) out[k] = std::floor(value / intervals[k]);
}

// Levels between two heights, per interval, added to `sums`.
void add_levels_between(double a, double b, std::span<const double> intervals, std::vector<double>& sums) {
    for (std::size_t k = 0; k < intervals.size(); ++k) {
        sums[k] += std::abs(std::floor(a / intervals[k]) - std::floor(b / intervals[k]));
    }
}

// A float's bits as an unsigned key that sorts as the floats do.
std::uint32_t order_key(float v) {
    const auto bits = std::bit_cast<std::uint32_t>(v);
    return bits & 0x80000000u ? ~bits : bits | 0x80000000u;
}

// The texels of a block as a dense grid: heights and which are valid.
struct Grid {
    int width = 0, height = 0;
    std::vector<float> z;
    std::vector<bool> valid;
    std::size_t at(int x, int y) const { return static_cast<std::size_t>(y) * width + x; }
};

Grid grid_of(const float* values, int width, int height, std::ptrdiff_t stride, float nodata) {
    Grid g{width, height, std::vector<float>(static_cast<std::size_t>(width) * height),
           std::vector<bool>(static_cast<std::size_t>(width) * height)};
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            const float v = values[y * stride + x];
            g.z[g.at(x, y)] = v;
            g.valid[g.at(x, y)] = v != nodata && std::isfinite(v);
        }
    }
    return g;
}

// Crossings of every level over the edges between valid neighbours, per interval.
std::vector<double> crossings(const Grid& g, std::span<const double> intervals) {
    const std::size_t k_count = intervals.size();
    std::vector<double> sums(k_count, 0.0), above(static_cast<std::size_t>(g.width) * k_count),
        row(static_cast<std::size_t>(g.width) * k_count);
    for (int y = 0; y < g.height; ++y) {
        for (int x = 0; x < g.width; ++x) {
            if (!g.valid[g.at(x, y)]) continue;
            double* q = &row[static_cast<std::size_t>(x) * k_count];
            level_indices(g.z[g.at(x, y)], intervals, q);
            for (std::size_t k = 0; k < k_count; ++k) {
                if (x > 0 && g.valid[g.at(x - 1, y)]) sums[k] += std::abs(q[k] - q[k - k_count]);
                if (y > 0 && g.valid[g.at(x, y - 1)]) sums[k] += std::abs(q[k] - above[x * k_count + k]);
            }
        }
        above.swap(row);
    }
    return sums;
}

// A union-find over the texels, each root keeping its component's first height (its birth: the
// extreme it grew from) and its last (where the sweep has reached it).
struct Components {
    std::vector<std::int32_t> parent;
    std::vector<float> birth, last;
    explicit Components(std::size_t n) : parent(n, -1), birth(n), last(n) {}
    std::int32_t find(std::int32_t i) {
        while (parent[i] != i) i = parent[i] = parent[parent[i]];
        return i;
    }
};

// One sweep over the valid texels in `order`: `down` from the highest for the regions above each level
// (8-connected), else up from the lowest for those below (4-connected). Each join of two components
// ends the younger one (the one born nearer the sweep), which stood as a region of its own at the
// levels between its birth and here. The sweep down also adds, for each component still standing at
// the end (one per connected part of the raster), the levels it spans: each part's lines counted
// once, not twice less one.
void sweep(const Grid& g, std::span<const std::uint32_t> order, bool down, std::span<const double> intervals,
           std::vector<double>& sums) {
    Components c(g.z.size());
    const bool eight = down;
    for (const std::uint32_t i : order) {
        const int x = static_cast<int>(i % g.width), y = static_cast<int>(i / g.width);
        const float v = g.z[i];
        c.parent[i] = static_cast<std::int32_t>(i), c.birth[i] = v, c.last[i] = v;
        for (int dy = -1; dy <= 1; ++dy) {
            for (int dx = -1; dx <= 1; ++dx) {
                if ((dx == 0 && dy == 0) || (!eight && dx != 0 && dy != 0)) continue;
                const int nx = x + dx, ny = y + dy;
                if (nx < 0 || ny < 0 || nx >= g.width || ny >= g.height) continue;
                const std::size_t n = g.at(nx, ny);
                if (c.parent[n] < 0) continue;  // not reached yet, or not valid
                std::int32_t a = c.find(static_cast<std::int32_t>(n)), b = c.find(static_cast<std::int32_t>(i));
                if (a == b) continue;
                const bool a_older = down ? c.birth[a] >= c.birth[b] : c.birth[a] <= c.birth[b];
                if (!a_older) std::swap(a, b);
                add_levels_between(c.birth[b], v, intervals, sums);  // b, the younger, ends here
                c.parent[b] = a;
                c.last[a] = v;
            }
        }
        c.last[c.find(static_cast<std::int32_t>(i))] = v;
    }
    if (!down) return;
    for (const std::uint32_t i : order) {
        if (c.parent[i] == static_cast<std::int32_t>(i)) add_levels_between(c.birth[i], c.last[i], intervals, sums);
    }
}

}  // namespace

std::vector<ContourCount> count_contours(const float* values, int width, int height, std::ptrdiff_t stride,
                                         float nodata, std::span<const double> intervals) {
    const Grid g = grid_of(values, width, height, stride, nodata);
    std::vector<std::uint32_t> order;
    order.reserve(g.z.size());
    for (std::uint32_t i = 0; i < g.z.size(); ++i) {
        if (g.valid[i]) order.push_back(i);
    }
    radix_sort(order, [&](std::uint32_t i) { return std::uint64_t{order_key(g.z[i])}; }, 32);  // lowest first
    std::vector<double> lines(intervals.size(), 0.0);
    sweep(g, order, false, intervals, lines);  // up: the regions below each level
    std::reverse(order.begin(), order.end());
    sweep(g, order, true, intervals, lines);   // down: the regions above, and each part once
    const std::vector<double> points = crossings(g, intervals);
    std::vector<ContourCount> out;
    for (std::size_t k = 0; k < intervals.size(); ++k) out.push_back({intervals[k], lines[k], points[k] + lines[k]});
    return out;
}

std::vector<double> contour_intervals(double interval, int coarser) {
    std::vector<double> out{interval};
    double p = std::pow(10.0, std::floor(std::log10(interval)));
    while (static_cast<int>(out.size()) <= coarser) {
        for (const double m : {1.0, 2.0, 5.0}) {
            if (m * p > interval * (1 + 1e-9) && static_cast<int>(out.size()) <= coarser) out.push_back(m * p);
        }
        p *= 10;
    }
    return out;
}

namespace {

// Crossings of the levels between the texels of row `a` and row `b` (or column), per interval, both valid.
void seam_crossings(std::span<const float> a, std::span<const float> b, float nodata,
                    std::span<const double> intervals, std::vector<double>& sums) {
    for (std::size_t i = 0; i < a.size(); ++i) {
        const bool valid = a[i] != nodata && b[i] != nodata && std::isfinite(a[i]) && std::isfinite(b[i]);
        if (valid) add_levels_between(a[i], b[i], intervals, sums);
    }
}

}  // namespace

std::vector<ContourCount> count_contours(const std::string& path, double nodata, std::span<const double> intervals) {
    GDALAllRegister();
    const QuietGdal quiet;
    const OpenRaster in{static_cast<GDALDataset*>(GDALOpen(path.c_str(), GA_ReadOnly))};
    if (!in.dataset) throw Error(path, std::nullopt, "cannot open the height raster: " + last_gdal_error());
    GDALRasterBand* band = in.dataset->GetRasterBand(1);
    const int width = in.dataset->GetRasterXSize(), height = in.dataset->GetRasterYSize();
    std::vector<ContourCount> total;
    for (const double interval : intervals) total.push_back({interval, 0, 0});
    std::vector<double> seams(intervals.size(), 0.0), crossed(intervals.size(), 0.0);  // levels over texel edges
    std::vector<float> block;
    const auto f_nodata = static_cast<float>(nodata);
    for (int y0 = 0; y0 < height; y0 += kContourBlock) {
        for (int x0 = 0; x0 < width; x0 += kContourBlock) {
            const int w = std::min(kContourBlock, width - x0), h = std::min(kContourBlock, height - y0);
            const int rw = std::min(w + 1, width - x0), rh = std::min(h + 1, height - y0);  // and the seams' texels
            block.resize(static_cast<std::size_t>(rw) * rh);
            if (band->RasterIO(GF_Read, x0, y0, rw, rh, block.data(), rw, rh, GDT_Float32, 0, 0) != CE_None) {
                throw Error(path, std::nullopt, "cannot read the height raster: " + last_gdal_error());
            }
            const auto counts = count_contours(block.data(), w, h, rw, f_nodata, intervals);
            for (std::size_t k = 0; k < counts.size(); ++k) {
                total[k].lines += counts[k].lines;
                crossed[k] += counts[k].vertices - counts[k].lines;
            }
            std::vector<float> left(h), right(h);
            for (int y = 0; rw > w && y < h; ++y) left[y] = block[y * rw + w - 1], right[y] = block[y * rw + w];
            if (rw > w) seam_crossings(left, right, f_nodata, intervals, seams);
            if (rh > h) {
                const std::span<const float> rows(block);
                seam_crossings(rows.subspan(static_cast<std::size_t>(h - 1) * rw, w),
                               rows.subspan(static_cast<std::size_t>(h) * rw, w), f_nodata, intervals, seams);
            }
        }
    }
    for (std::size_t k = 0; k < total.size(); ++k) {  // a line crossing a seam was counted in each block
        total[k].lines = std::max(total[k].lines - seams[k] / 2, 0.0);
        total[k].vertices = crossed[k] + seams[k] + total[k].lines;
    }
    return total;
}

std::uint64_t contour_memory_bytes(const ContourCount& count, double texels) {
    constexpr double kBytesPerPoint = 40, kProgramBytes = 64e6;  // the program itself, as full_dem.cpp counts it
    const double cache = std::min(texels * sizeof(float), static_cast<double>(GDALGetCacheMax64()));
    const double bytes = kProgramBytes + cache + count.vertices * kBytesPerPoint;
    return bytes >= 1.8e19 ? ~0ull : static_cast<std::uint64_t>(bytes);
}

}  // namespace lidarscout::raster
