// Patch space: the geometry of one heightmap patch and its padded window, the chunk points of
// that window in normalised form (what every reconstruction method and the network work on),
// and the image type the methods fill.
//
// Geometry (defaults: 10 m texels, 64 x 64 patch, 16 texels of padding on each side):
//   - the patch covers [patch_min, patch_min + patch_texels * texel_m) on x and y;
//   - the window is the patch grown by pad_texels on every side: 96 x 96 texels, 960 m;
//   - texel (row j, column i) of the window covers
//       x in [window_min_x + i * texel_m, window_min_x + (i + 1) * texel_m),
//       y in [window_min_y + j * texel_m, window_min_y + (j + 1) * texel_m)
//     and is sampled at its centre. Column i grows with x (east), row j grows with y (north):
//     row 0 is the southern edge of the window (a north-up picture shows row 0 at the bottom).
//
// Normalisation (what the network sees; keep in sync with python/):
//   - radius r = window_m / 2 (480 m by default);
//   - positions: p' = (p - c) / r with c the window (= patch) centre, so the window is
//     exactly [-1, 1]^2; texel centres sit at -1 + (i + 0.5) * 2 / 96;
//   - heights: h' = (z - centre_z) / r, with centre_z = the median of the heights of the
//     window's chunk points (after merging duplicates; for an even count the mean of the two
//     middle values). The paper takes the linearly interpolated height at the patch centre
//     instead; the median is used here because one outlier (a bird, a mast) next to the centre
//     would shift every height of the patch, and it needs no triangulation;
//   - colours: 8-bit channels / 255, floats in [0, 1]; NaN when the survey has no colour
//     (PatchOptions::has_rgb = false). The network replaces NaN by 0 (height) / 0.5 (colour).
//   Back to metres: z = centre_z + h' * r (PatchPoints::to_metres).
//
// Inside the library positions are kept in exact fixed point: grid units of 1/65536 texel
// from the window's min corner (0.15 mm at 10 m texels). Every point is snapped to that grid
// once, so the triangulation, the face map, the nearest-neighbour search and the tests all
// see the same coordinates, and orientation tests and squared distances are exact in double
// arithmetic (coordinates below 2^25).
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "core/patch_grid.hpp"

namespace lidarscout::recon {

inline constexpr std::int64_t kGridUnitsPerTexel = 65536;
inline constexpr float kNoValue = std::numeric_limits<float>::quiet_NaN();

struct PatchSpec {
    double texel_m = 10.0;  // metres per texel (10 m as in the paper; 1, 2.5, 5 m also work)
    int patch_texels = 64;  // texels per patch side
    int pad_texels = 16;    // texels of context on each side of the patch

    int window_texels() const { return patch_texels + 2 * pad_texels; }
    double patch_m() const { return patch_texels * texel_m; }
    double pad_m() const { return pad_texels * texel_m; }
    double window_m() const { return window_texels() * texel_m; }
    double radius_m() const { return 0.5 * window_m(); }
    // The window's side in grid units.
    std::int64_t grid_extent() const { return std::int64_t{window_texels()} * kGridUnitsPerTexel; }

    // Throws lidarscout::Error unless texel_m is positive and finite, patch_texels >= 1,
    // pad_texels >= 0 and the window has at most 512 texels per side (exact arithmetic).
    void validate() const;
};

enum class PatchStatus : std::uint8_t {
    Ok,
    TooFewPoints,  // fewer distinct chunk points than PatchOptions::min_points: no images
};

struct PatchOptions {
    PatchSpec spec;
    std::size_t min_points = 25;  // as the reference implementation; at least 1 is always needed
    bool has_rgb = true;          // false: colours are NaN (the survey has none)
};

// A position in grid units (exact integers held in doubles).
struct GridXY {
    double x = 0, y = 0;
    bool operator==(const GridXY&) const = default;
};

// One chunk point of the window in normalised form.
struct PatchPoint {
    std::int32_t gx = 0, gy = 0;  // grid units from the window's min corner, in [0, grid_extent]
    float h = 0;                  // normalised height (see the top of this file)
    float r = 0, g = 0, b = 0;    // colour in [0, 1], NaN without colour
    GridXY xy() const { return {static_cast<double>(gx), static_cast<double>(gy)}; }
};

// The chunk points of one window, sorted by (gy, gx), one point per position: chunk points that
// snap to the same position are merged into one with the mean height and colour.
struct PatchPoints {
    PatchSpec spec;
    PatchStatus status = PatchStatus::TooFewPoints;
    double window_min_x = 0, window_min_y = 0;  // metres
    double centre_z = std::numeric_limits<double>::quiet_NaN();  // metres
    bool has_rgb = true;
    std::size_t window_count = 0;  // chunk points inside the window, before merging
    std::vector<PatchPoint> points;

    int size() const { return spec.window_texels(); }
    double to_metres(double h) const { return centre_z + h * spec.radius_m(); }
    double normalise(double z_m) const { return (z_m - centre_z) / spec.radius_m(); }
    // Position in patch space [-1, 1]^2.
    double patch_x(const PatchPoint& p) const { return grid_to_patch(p.gx); }
    double patch_y(const PatchPoint& p) const { return grid_to_patch(p.gy); }
    double grid_to_patch(double grid) const { return grid / (0.5 * spec.grid_extent()) - 1.0; }
    // Metres of the centre of texel column `col` / row `row` of the window.
    double texel_centre_x(int col) const { return window_min_x + (col + 0.5) * spec.texel_m; }
    double texel_centre_y(int row) const { return window_min_y + (row + 0.5) * spec.texel_m; }
};

// The chunk points of the padded window around the patch whose min corner is
// (patch_min_x, patch_min_y) (metres, the same frame as the points). Points outside the window
// [patch_min - pad_m, patch_min + patch_m + pad_m) are ignored. Throws lidarscout::Error for a
// bad spec or a point with a non-finite coordinate.
PatchPoints make_patch_points(std::span<const lidarscout::OverviewPoint> points, double patch_min_x,
                              double patch_min_y, const PatchOptions& options = {});
// The same for cell `cell` of `grid` (grid.window(cell, pad_m)); the grid's patch size must
// equal the spec's patch_m.
PatchPoints make_patch_points(const lidarscout::PatchGrid& grid, lidarscout::CellKey cell,
                              const PatchOptions& options = {});

// Snaps points to the grid of the window of `spec` whose min corner is (window_min_x,
// window_min_y), as make_patch_points does: snap() gives a point's grid position (gx, gy), or
// false for a point outside the window (or with a non-finite coordinate).
class GridSnap {
public:
    GridSnap(const PatchSpec& spec, double window_min_x, double window_min_y)
        : units_per_metre_(kGridUnitsPerTexel / spec.texel_m), window_m_(spec.window_m()), min_x_(window_min_x),
          min_y_(window_min_y) {}
    bool snap(double x, double y, std::int32_t& gx, std::int32_t& gy) const {
        const double dx = x - min_x_, dy = y - min_y_;
        if (!(dx >= 0.0 && dx < window_m_ && dy >= 0.0 && dy < window_m_)) return false;
        gx = static_cast<std::int32_t>(std::llround(dx * units_per_metre_));
        gy = static_cast<std::int32_t>(std::llround(dy * units_per_metre_));
        return true;
    }

private:
    double units_per_metre_, window_m_, min_x_, min_y_;
};

// The positions of the points, in their order.
std::vector<GridXY> grid_positions(const PatchPoints& patch);

// Per-point values, channel-major: value(c, i) = values[c * count + i].
struct PointValues {
    int channels = 0;
    std::size_t count = 0;
    std::vector<float> values;
    float value(int channel, std::size_t point) const { return values[channel * count + point]; }
};
PointValues height_values(const PatchPoints& patch);  // 1 channel: normalised heights
PointValues colour_values(const PatchPoints& patch);  // 3 channels: r, g, b in [0, 1] (or NaN)

// A square image, channel-major (planar, as a network tensor C x H x W):
// value(row, col, c) = values[(c * size + row) * size + col]; NaN = no value.
struct Image {
    int size = 0;
    int channels = 0;
    std::vector<float> values;

    Image() = default;
    Image(int size_texels, int channel_count, float fill = kNoValue)
        : size(size_texels), channels(channel_count),
          values(static_cast<std::size_t>(size_texels) * size_texels * channel_count, fill) {}
    bool empty() const { return values.empty(); }
    std::size_t texels() const { return static_cast<std::size_t>(size) * size; }
    float& at(int row, int col, int channel = 0) { return values[index(row, col, channel)]; }
    float at(int row, int col, int channel = 0) const { return values[index(row, col, channel)]; }
    std::span<float> plane(int channel) { return {values.data() + channel * texels(), texels()}; }
    std::span<const float> plane(int channel) const { return {values.data() + channel * texels(), texels()}; }
    std::size_t index(int row, int col, int channel) const {
        return (static_cast<std::size_t>(channel) * size + row) * size + col;
    }
};

// The centre size x size texels of `image` (e.g. the 64 x 64 patch of a 96 x 96 window).
// Throws lidarscout::Error when size exceeds the image or the margin is odd.
Image crop_centre(const Image& image, int size);

}  // namespace lidarscout::recon
