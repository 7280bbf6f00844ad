// profile_image: the plot's scale, its grid and the points as dots.
#include "pipelines/profile_image.hpp"

#include <algorithm>
#include <cmath>

#include "render/colour_modes.hpp"
#include "render/framebuffer.hpp"

namespace lidarscout::pipelines {
namespace {

constexpr int kMargin = 24;

// 1, 2 or 5 times a power of ten, so that `span` holds about `lines` steps.
double round_step(double span, double lines) {
    const double raw = span / lines, p = std::pow(10.0, std::floor(std::log10(raw)));
    for (const double m : {1.0, 2.0, 5.0}) {
        if (m * p >= raw) return m * p;
    }
    return 10 * p;
}

struct Plot {
    double length, z_min, z_max, px_per_d, px_per_z;
    int width, height;
    int px(double d) const { return kMargin + static_cast<int>(std::lround(d * px_per_d)); }
    int py(double z) const { return height - kMargin - static_cast<int>(std::lround((z - z_min) * px_per_z)); }
};

// Distance across the width, the heights' range (a tenth more on each side) across the height.
Plot plot_of(const Profile& profile, const Corridor& corridor, int width, int height) {
    double lo = INFINITY, hi = -INFINITY;
    for (const auto& p : profile.points) lo = std::min(lo, p.z), hi = std::max(hi, p.z);
    if (!(lo <= hi)) lo = 0, hi = 1;
    const double pad = std::max(0.5, (hi - lo) / 10);
    Plot plot{corridor.length(), lo - pad, hi + pad, 0, 0, width, height};
    plot.px_per_d = (width - 2.0 * kMargin) / plot.length;
    plot.px_per_z = (height - 2.0 * kMargin) / (plot.z_max - plot.z_min);
    return plot;
}

void put(render::RgbaImage& image, int x, int y, std::uint32_t colour) {
    if (x < 0 || y < 0 || x >= image.width || y >= image.height) return;
    image.pixels[std::size_t(y) * image.width + x] = colour;
}

void draw_grid(render::RgbaImage& image, const Plot& plot, double d_step, double z_step) {
    const std::uint32_t grid = render::pack_rgba(60, 64, 72), axis = render::pack_rgba(150, 150, 160);
    for (double d = 0; d <= plot.length + 1e-9; d += d_step) {
        for (int y = kMargin; y < plot.height - kMargin; ++y) put(image, plot.px(d), y, d == 0 ? axis : grid);
    }
    for (double z = std::ceil(plot.z_min / z_step) * z_step; z <= plot.z_max; z += z_step) {
        for (int x = kMargin; x <= plot.px(plot.length); ++x) put(image, x, plot.py(z), grid);
    }
    for (int x = kMargin; x <= plot.px(plot.length); ++x) put(image, x, plot.height - kMargin, axis);
}

}  // namespace

render::RgbaImage profile_image(const Profile& profile, const Corridor& corridor, int width, int height,
                                ProfileImageScale* scale, ProfileColours colours, double ramp_min, double ramp_max) {
    const Plot plot = plot_of(profile, corridor, width, height);
    render::RgbaImage image{plot.width, plot.height, {}};
    image.pixels.assign(std::size_t(image.width) * image.height, render::pack_rgba(24, 26, 32));
    const double d_step = round_step(plot.length, 10), z_step = round_step(plot.z_max - plot.z_min, 6);
    draw_grid(image, plot, d_step, z_step);
    if (!(ramp_max > ramp_min)) ramp_min = plot.z_min, ramp_max = plot.z_max;
    for (const auto& p : profile.points) {
        const std::uint32_t c =
            colours == ProfileColours::Elevation
                ? render::elevation_ramp(static_cast<float>((p.z - ramp_min) / (ramp_max - ramp_min)))
                : render::classification_colour(p.classification);
        const int x = plot.px(p.distance), y = plot.py(p.z);
        put(image, x, y, c), put(image, x + 1, y, c), put(image, x, y + 1, c), put(image, x + 1, y + 1, c);
    }
    if (scale) *scale = {plot.z_min, plot.z_max, d_step, z_step};
    return image;
}

}  // namespace lidarscout::pipelines
