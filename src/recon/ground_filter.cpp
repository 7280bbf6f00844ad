// The simple morphological ground filter (see ground_filter.hpp): minimum surface, low outliers,
// progressive opening with square windows (separable running minima and maxima, van Herk /
// Gil-Werman: three comparisons per cell whatever the window), provisional surface, and the
// points within a slope-dependent threshold of it.
#include "recon/ground_filter.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <utility>

#include "core/error.hpp"
#include "recon/hole_fill.hpp"

namespace lidarscout::recon {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr double kLowOutlierSlope = 5.0;  // SMRF's pits: steeper than this against a neighbour
constexpr double kDefaultSlope = 0.15;    // PDAL's

using Raster = std::vector<float>;  // cells x cells, rows from the south

struct Lattice {
    int n;
    std::size_t at(int i, int j) const { return static_cast<std::size_t>(j) * n + i; }
};

template <bool Min>
float pick(float a, float b) {
    return Min ? std::min(a, b) : std::max(a, b);
}

// The running min (`Min` true) or max over windows of 2r + 1 along one axis (van Herk / Gil-Werman:
// prefix and suffix extremes within runs of 2r + 1, two of them per output), out of range
// ignored, along the columns of `m` rows of `width` floats (each step a vectorisable loop over a row).
template <bool Min>
void running_axis(const float* in, float* out, int m, std::size_t width, int r, std::vector<float>& g,
                  std::vector<float>& h) {
    const std::size_t stride = width;
    const int w = 2 * r + 1;
    const int padded = (m + 2 * r + w - 1) / w * w;
    g.resize(static_cast<std::size_t>(padded) * width), h.resize(g.size());
    const float identity = Min ? kInf : -kInf;
    const auto at = [&](std::vector<float>& v, int k) { return v.data() + static_cast<std::size_t>(k) * width; };
    const auto value = [&](int k, std::size_t x) { return k >= r && k < m + r ? in[(k - r) * stride + x] : identity; };
    for (int k = 0; k < padded; ++k) {
        float* gk = at(g, k);
        if (k % w == 0) {
            for (std::size_t x = 0; x < width; ++x) gk[x] = value(k, x);
        } else {
            const float* prev = at(g, k - 1);
            for (std::size_t x = 0; x < width; ++x) gk[x] = pick<Min>(prev[x], value(k, x));
        }
    }
    for (int k = padded - 1; k >= 0; --k) {
        float* hk = at(h, k);
        if (k % w == w - 1) {
            for (std::size_t x = 0; x < width; ++x) hk[x] = value(k, x);
        } else {
            const float* next = at(h, k + 1);
            for (std::size_t x = 0; x < width; ++x) hk[x] = pick<Min>(next[x], value(k, x));
        }
    }
    for (int i = 0; i < m; ++i) {
        const float *hi = at(h, i), *gi = at(g, i + w - 1);
        for (std::size_t x = 0; x < width; ++x) out[i * stride + x] = pick<Min>(hi[x], gi[x]);
    }
}

// The running min or max over windows of 3 along the columns (the same as running_axis with r 1,
// in one pass: SMRF's erosions at radius 1).
template <bool Min>
void running_columns_3(const float* in, float* out, int n) {
    const auto w = static_cast<std::size_t>(n);
    for (int j = 0; j < n; ++j) {
        const float* mid = in + j * w;
        const float* below = j > 0 ? mid - w : mid;
        const float* above = j + 1 < n ? mid + w : mid;
        float* o = out + j * w;
        for (std::size_t x = 0; x < w; ++x) o[x] = pick<Min>(pick<Min>(below[x], mid[x]), above[x]);
    }
}

// `in` transposed (n x n) into `out`, in tiles that stay in cache.
void transpose(const float* in, float* out, int n) {
    constexpr int kTile = 8;  // the 8 rows a tile writes (2 KB apart at n 512) stay in L1; 32 thrashed it
    const auto w = static_cast<std::size_t>(n);
    for (int j0 = 0; j0 < n; j0 += kTile) {
        for (int i0 = 0; i0 < n; i0 += kTile) {
            const int j1 = std::min(n, j0 + kTile), i1 = std::min(n, i0 + kTile);
            for (int j = j0; j < j1; ++j) {
                for (int i = i0; i < i1; ++i) out[i * w + j] = in[j * w + i];
            }
        }
    }
}

// The running min or max over a square window of half-width r: along the columns, then along the
// rows as the columns of the transpose (every pass a vectorisable loop over whole rows).
template <bool Min>
Raster running_2d(const Raster& in, const Lattice& l, int r) {
    Raster a(in.size()), b(in.size());
    std::vector<float> g, h;
    const auto n = static_cast<std::size_t>(l.n);
    const auto columns = [&](const Raster& from, Raster& to) {
        if (r == 1) running_columns_3<Min>(from.data(), to.data(), l.n);
        else running_axis<Min>(from.data(), to.data(), l.n, n, r, g, h);
    };
    columns(in, a);
    transpose(a.data(), b.data(), l.n);
    columns(b, a);
    transpose(a.data(), b.data(), l.n);
    return b;
}

// SMRF's progressive filter: 1 where a cell drops by more than slope x radius x cell when the
// surface is opened with radius 1 .. max_radius. With square windows the opening of the last
// opening at the next radius is the opening of the surface itself there, and an erosion at radius
// r is the erosion at r - 1 eroded at radius 1: so each radius costs one small erosion and one
// dilation.
std::vector<std::uint8_t> object_mask(const Raster& z, const Lattice& l, double slope, double cell_m,
                                      int max_radius) {
    std::vector<std::uint8_t> object(z.size(), 0);
    Raster last = z, eroded = z;
    for (int r = 1; r <= max_radius; ++r) {
        eroded = running_2d<true>(eroded, l, 1);
        Raster now = running_2d<false>(eroded, l, r);
        const float limit = static_cast<float>(slope * r * cell_m);
        const float *before = last.data(), *after = now.data();
        std::uint8_t* marked = object.data();
        for (std::size_t c = 0; c < z.size(); ++c) marked[c] |= static_cast<std::uint8_t>(before[c] - after[c] > limit);
        last = std::move(now);
    }
    return object;
}

// `z` with its NaN cells filled; false when no cell is defined.
bool filled(Raster& z, const Lattice& l) { return hole_fill(z, l.n, std::vector<bool>(z.size(), true)); }

// Rise over run of the surface at each cell (central differences, one-sided at the edges).
Raster slopes(const Raster& z, const Lattice& l, double cell_m) {
    Raster out(z.size());
    const auto diff = [&](int a0, int a1, float va0, float va1) {
        return (va1 - va0) / static_cast<float>((a1 - a0) * cell_m);
    };
    for (int j = 0; j < l.n; ++j) {
        for (int i = 0; i < l.n; ++i) {
            const int i0 = std::max(i - 1, 0), i1 = std::min(i + 1, l.n - 1);
            const int j0 = std::max(j - 1, 0), j1 = std::min(j + 1, l.n - 1);
            const float gx = i1 > i0 ? diff(i0, i1, z[l.at(i0, j)], z[l.at(i1, j)]) : 0.0f;
            const float gy = j1 > j0 ? diff(j0, j1, z[l.at(i, j0)], z[l.at(i, j1)]) : 0.0f;
            out[l.at(i, j)] = std::sqrt(gx * gx + gy * gy);
        }
    }
    return out;
}

// A sample's position in cells from the lattice's south-west corner.
std::pair<double, double> in_cells(const GroundLattice& l, const GroundSample& s) {
    return {(s.x - l.min_x) / l.cell_m, (s.y - l.min_y) / l.cell_m};
}

std::string number(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", v);
    return text;
}

void check_positive(double v, const char* what, double most) {
    if (!(v > 0) || !(v <= most)) {
        throw Error(std::string(what) + " must be a positive number of at most " + number(most) + " (it is " +
                    number(v) + ")");
    }
}

// SMRF's slope when none is given: the terrain's steepness, the 75th percentile of the slopes
// between neighbouring window-sized cells' lowest points (objects narrower than the window leave
// those on the ground), at least PDAL's default 0.15 (flat and rolling land keep it) and at most
// 1. The filter's default is too strict for steep land: on the Red River Gorge tile it left 5.6 %
// of the 1 m dtm empty (cliffs and slopes taken for objects), with this 2.2 %.
double terrain_slope(const Raster& zmin, const std::vector<std::uint8_t>& empty, const Lattice& l, double cell_m,
                     double window_m) {
    const int k = std::max(1, static_cast<int>(std::round(window_m / cell_m)));
    const int m = (l.n + k - 1) / k;
    Raster lowest(static_cast<std::size_t>(m) * m, kInf);
    for (int j = 0; j < l.n; ++j) {
        for (int i = 0; i < l.n; ++i) {
            float& c = lowest[static_cast<std::size_t>(j / k) * m + i / k];
            if (!empty[l.at(i, j)]) c = std::min(c, zmin[l.at(i, j)]);
        }
    }
    std::vector<float> slopes;
    const auto add = [&](float a, float b) {
        if (a != kInf && b != kInf) slopes.push_back(std::abs(a - b) / static_cast<float>(k * cell_m));
    };
    for (int j = 0; j < m; ++j) {
        for (int i = 0; i < m; ++i) {
            const float a = lowest[static_cast<std::size_t>(j) * m + i];
            if (i + 1 < m) add(a, lowest[static_cast<std::size_t>(j) * m + i + 1]);
            if (j + 1 < m) add(a, lowest[static_cast<std::size_t>(j + 1) * m + i]);
        }
    }
    if (slopes.empty()) return kDefaultSlope;
    auto q = slopes.begin() + static_cast<std::ptrdiff_t>(slopes.size() * 3 / 4);
    std::nth_element(slopes.begin(), q, slopes.end());
    return std::clamp(static_cast<double>(*q), kDefaultSlope, 1.0);
}

// The lattice with cells as large as the samples' spacing where they are sparser than one per
// cell: a cell without a point has no lowest point, and a surface made mostly of filled holes
// would make single points look like objects. The density is counted over the coarse cells
// (8 x 8 cells) that hold samples, so that the edge of a survey does not look sparse.
GroundLattice sparse_adapted(std::span<const GroundSample> samples, const GroundLattice& lattice) {
    constexpr int kCoarse = 8;
    const int n = (lattice.cells + kCoarse - 1) / kCoarse;
    std::vector<std::uint8_t> occupied(static_cast<std::size_t>(n) * n, 0);
    std::size_t inside = 0;
    for (const GroundSample& s : samples) {
        const auto [u, v] = in_cells(lattice, s);
        if (!(u >= 0 && u < lattice.cells && v >= 0 && v < lattice.cells)) continue;
        occupied[static_cast<std::size_t>(v / kCoarse) * n + static_cast<std::size_t>(u / kCoarse)] = 1;
        ++inside;
    }
    const auto coarse_cells = static_cast<double>(std::count(occupied.begin(), occupied.end(), 1));
    if (inside == 0) return lattice;
    const double area = coarse_cells * kCoarse * kCoarse * lattice.cell_m * lattice.cell_m;
    const double spacing = std::sqrt(area / static_cast<double>(inside));
    if (spacing <= lattice.cell_m) return lattice;
    GroundLattice out = lattice;
    const double side = lattice.cells * lattice.cell_m;
    out.cells = std::max(1, static_cast<int>(std::ceil(side / spacing)));
    out.cell_m = side / out.cells;
    return out;
}

}  // namespace

void check_ground_params(const GroundFilterParams& p) {
    check_positive(p.cell_m, "--ground-cell (metres)", 100);
    if (p.slope != 0) check_positive(p.slope, "--ground-slope (rise over run)", 10);  // 0: from the terrain
    check_positive(p.window_m, "--ground-window (metres)", 1000);
    check_positive(p.threshold_m, "--ground-threshold (metres)", 100);
    if (!(p.scalar >= 0) || !(p.scalar <= 100)) throw Error("the ground filter's scalar must be in 0 .. 100");
    if (p.window_m < p.cell_m) {
        throw Error("--ground-window (" + number(p.window_m) + " m) must be at least the cell (" + number(p.cell_m) +
                    " m)");
    }
}

GroundLattice ground_lattice(double min_x, double min_y, double side_m, const GroundFilterParams& p, int max_cells) {
    GroundLattice l;
    l.min_x = min_x, l.min_y = min_y;
    l.cell_m = std::max(p.cell_m, side_m / max_cells);
    l.cells = std::max(1, static_cast<int>(std::ceil(side_m / l.cell_m - 1e-9)));
    return l;
}

int opening_radius_cells(const GroundFilterParams& p, double cell_m) {
    return std::max(1, static_cast<int>(std::ceil(p.window_m / cell_m)));
}

double ground_filter_reach_m(const GroundFilterParams& p, double cell_m) {
    return (2.0 * opening_radius_cells(p, cell_m) + 2) * cell_m;
}

std::vector<std::uint8_t> find_ground(std::span<const GroundSample> samples, const GroundLattice& given,
                                      const GroundFilterParams& p) {
    const GroundLattice lattice = sparse_adapted(samples, given);
    const Lattice l{lattice.cells};
    std::vector<std::uint8_t> ground(samples.size(), 0);
    std::vector<std::int64_t> cell_of(samples.size(), -1);
    Raster zmin(static_cast<std::size_t>(l.n) * l.n, kInf);
    for (std::size_t s = 0; s < samples.size(); ++s) {
        const auto [u, v] = in_cells(lattice, samples[s]);
        if (!(u >= 0 && u < l.n && v >= 0 && v < l.n)) continue;
        const std::size_t c = l.at(static_cast<int>(u), static_cast<int>(v));
        cell_of[s] = static_cast<std::int64_t>(c);
        zmin[c] = std::min(zmin[c], samples[s].z);
    }
    std::vector<std::uint8_t> empty(zmin.size());
    for (std::size_t c = 0; c < zmin.size(); ++c) {
        empty[c] = zmin[c] == kInf;
        if (empty[c]) zmin[c] = NAN;
    }
    if (!filled(zmin, l)) return ground;

    Raster negated(zmin.size());
    std::transform(zmin.begin(), zmin.end(), negated.begin(), [](float z) { return -z; });
    const std::vector<std::uint8_t> low = object_mask(negated, l, kLowOutlierSlope, lattice.cell_m, 1);
    const int max_radius = opening_radius_cells(p, lattice.cell_m);
    const double steepest = p.slope > 0 ? p.slope : terrain_slope(zmin, empty, l, lattice.cell_m, p.window_m);
    const std::vector<std::uint8_t> object = object_mask(zmin, l, steepest, lattice.cell_m, max_radius);

    Raster surface = zmin;
    for (std::size_t c = 0; c < surface.size(); ++c) {
        if (empty[c] || low[c] || object[c]) surface[c] = NAN;
    }
    if (!filled(surface, l)) return ground;
    const Raster slope = slopes(surface, l, lattice.cell_m);

    for (std::size_t s = 0; s < samples.size(); ++s) {
        if (cell_of[s] < 0) continue;
        const auto [u, v] = in_cells(lattice, samples[s]);
        const float limit = static_cast<float>(p.threshold_m + p.scalar * slope[static_cast<std::size_t>(cell_of[s])]);
        ground[s] = std::abs(samples[s].z - sample_bilinear(surface, l.n, u, v)) <= limit ? 1 : 0;
    }
    return ground;
}

}  // namespace lidarscout::recon
