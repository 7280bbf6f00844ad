// Patch space: snapping a window's chunk points to the fixed-point grid, merging duplicates,
// the centre height and the normalisation (definitions in patch_space.hpp).
#include "recon/patch_space.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <string>
#include <tuple>

#include "core/error.hpp"
#include "core/radix_sort.hpp"

namespace lidarscout::recon {
namespace {

// A window point snapped to the grid, before duplicates are merged.
struct Snapped {
    std::int32_t gx, gy;
    double z;
    lidarscout::Rgb8 rgb;

    auto key() const { return std::tie(gy, gx, z, rgb.r, rgb.g, rgb.b); }
};

std::vector<Snapped> snap_window(std::span<const lidarscout::OverviewPoint> points, const PatchSpec& spec,
                                 double window_min_x, double window_min_y) {
    const GridSnap grid(spec, window_min_x, window_min_y);
    std::vector<Snapped> out;
    out.reserve(points.size());
    for (const auto& p : points) {
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
            throw Error::in_stage("recon", "chunk point with a non-finite coordinate");
        }
        std::int32_t gx = 0, gy = 0;
        if (grid.snap(p.x, p.y, gx, gy)) out.push_back({gx, gy, p.z, p.rgb});
    }
    // A canonical order (not the input order) so that the result does not depend on it: by
    // position (a radix sort), then the few points at one position by height and colour.
    const int bits = std::bit_width(static_cast<std::uint64_t>(spec.grid_extent()));
    radix_sort(out, [bits](const Snapped& s) { return std::uint64_t(s.gy) << bits | std::uint64_t(s.gx); }, 2 * bits);
    const auto by_key = [](const Snapped& a, const Snapped& b) { return a.key() < b.key(); };
    for (std::size_t i = 0; i < out.size();) {
        std::size_t j = i + 1;
        while (j < out.size() && out[j].gx == out[i].gx && out[j].gy == out[i].gy) ++j;
        if (j - i > 1) std::sort(out.begin() + i, out.begin() + j, by_key);
        i = j;
    }
    return out;
}

// Points at the same grid position become one with the mean height and colour: the patch points
// (their colours final, their heights 0) and their mean heights in `mean_z`, from which the caller
// sets the heights once it knows the centre's.
std::vector<PatchPoint> merge_duplicates(const std::vector<Snapped>& sorted, bool has_rgb,
                                         std::vector<double>& mean_z) {
    std::vector<PatchPoint> out;
    out.reserve(sorted.size()), mean_z.clear(), mean_z.reserve(sorted.size());
    const float no_colour = kNoValue;
    for (std::size_t i = 0; i < sorted.size();) {
        std::size_t j = i;
        double z = 0, r = 0, g = 0, b = 0;  // 0..255
        for (; j < sorted.size() && sorted[j].gx == sorted[i].gx && sorted[j].gy == sorted[i].gy; ++j) {
            z += sorted[j].z, r += sorted[j].rgb.r, g += sorted[j].rgb.g, b += sorted[j].rgb.b;
        }
        const double n = static_cast<double>(j - i);
        PatchPoint p;
        p.gx = sorted[i].gx, p.gy = sorted[i].gy, p.h = 0;
        p.r = has_rgb ? static_cast<float>(r / n / 255.0) : no_colour;
        p.g = has_rgb ? static_cast<float>(g / n / 255.0) : no_colour;
        p.b = has_rgb ? static_cast<float>(b / n / 255.0) : no_colour;
        out.push_back(p);
        mean_z.push_back(z / n);
        i = j;
    }
    return out;
}

double median_height(std::vector<double> z) {
    if (z.empty()) return std::numeric_limits<double>::quiet_NaN();
    const std::size_t mid = z.size() / 2;
    std::nth_element(z.begin(), z.begin() + mid, z.end());
    if (z.size() % 2 == 1) return z[mid];
    const double upper = z[mid];
    const double lower = *std::max_element(z.begin(), z.begin() + mid);
    return 0.5 * (lower + upper);
}

}  // namespace

void PatchSpec::validate() const {
    if (!(texel_m > 0.0) || !std::isfinite(texel_m)) {
        throw Error::in_stage("recon", "texel size must be positive and finite");
    }
    if (patch_texels < 1 || pad_texels < 0) throw Error::in_stage("recon", "patch needs >= 1 texel and padding >= 0");
    if (window_texels() > 512) {
        throw Error::in_stage("recon",
                              "window of " + std::to_string(window_texels()) + " texels exceeds the limit of 512");
    }
}

PatchPoints make_patch_points(std::span<const lidarscout::OverviewPoint> points, double patch_min_x,
                              double patch_min_y, const PatchOptions& options) {
    options.spec.validate();
    PatchPoints patch;
    patch.spec = options.spec;
    patch.has_rgb = options.has_rgb;
    patch.window_min_x = patch_min_x - options.spec.pad_m();
    patch.window_min_y = patch_min_y - options.spec.pad_m();

    const auto snapped = snap_window(points, options.spec, patch.window_min_x, patch.window_min_y);
    patch.window_count = snapped.size();
    std::vector<double> mean_z;
    patch.points = merge_duplicates(snapped, options.has_rgb, mean_z);
    patch.centre_z = median_height(mean_z);
    const double radius = options.spec.radius_m();
    for (std::size_t i = 0; i < patch.points.size(); ++i) {
        patch.points[i].h = static_cast<float>((mean_z[i] - patch.centre_z) / radius);
    }
    const std::size_t needed = std::max<std::size_t>(options.min_points, 1);
    patch.status = patch.points.size() >= needed ? PatchStatus::Ok : PatchStatus::TooFewPoints;
    return patch;
}

PatchPoints make_patch_points(const PatchGrid& grid, CellKey cell, const PatchOptions& options) {
    options.spec.validate();
    const double patch_m = options.spec.patch_m();
    if (std::abs(grid.patch_size() - patch_m) > 1e-9 * patch_m) {
        throw Error::in_stage("recon", "the grid's cells (" + std::to_string(grid.patch_size()) +
                    " m) are not the patches of the spec (" + std::to_string(patch_m) + " m)");
    }
    const auto window = grid.window(cell, options.spec.pad_m());
    return make_patch_points(window, grid.cell_min_x(cell), grid.cell_min_y(cell), options);
}

std::vector<GridXY> grid_positions(const PatchPoints& patch) {
    std::vector<GridXY> out(patch.points.size());
    std::transform(patch.points.begin(), patch.points.end(), out.begin(), [](const PatchPoint& p) { return p.xy(); });
    return out;
}

PointValues height_values(const PatchPoints& patch) {
    PointValues v{1, patch.points.size(), std::vector<float>(patch.points.size())};
    for (std::size_t i = 0; i < patch.points.size(); ++i) v.values[i] = patch.points[i].h;
    return v;
}

PointValues colour_values(const PatchPoints& patch) {
    const std::size_t n = patch.points.size();
    PointValues v{3, n, std::vector<float>(3 * n)};
    for (std::size_t i = 0; i < n; ++i) {
        v.values[i] = patch.points[i].r;
        v.values[n + i] = patch.points[i].g;
        v.values[2 * n + i] = patch.points[i].b;
    }
    return v;
}

Image crop_centre(const Image& image, int size) {
    const int margin2 = image.size - size;
    if (size < 0 || margin2 < 0 || margin2 % 2 != 0) {
        throw Error::in_stage("recon", "cannot crop " + std::to_string(size) + " texels from the centre of " +
                    std::to_string(image.size));
    }
    const int margin = margin2 / 2;
    Image out(size, image.channels);
    for (int c = 0; c < image.channels; ++c) {
        for (int row = 0; row < size; ++row) {
            for (int col = 0; col < size; ++col) out.at(row, col, c) = image.at(row + margin, col + margin, c);
        }
    }
    return out;
}

}  // namespace lidarscout::recon
