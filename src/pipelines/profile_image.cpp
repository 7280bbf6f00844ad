// profile_image: the plot's layout and scale, its grid, the points as dots in class order, the labels.
#include "pipelines/profile_image.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <vector>

#include "core/error.hpp"
#include "dataset/dataset.hpp"
#include "las/crs.hpp"
#include "render/bitmap_font.hpp"
#include "render/colour_modes.hpp"
#include "render/framebuffer.hpp"

namespace lidarscout::pipelines {
namespace {

constexpr int kMargin = 24;          // the bare plot's margin on every side
constexpr int kTextScale = 2;        // font pixels drawn as 2 x 2: 10 x 14 pixel characters
constexpr int kTick = 6, kGap = 8;   // tick marks' length; the space between a tick, its label and a title
constexpr int kMinPlotHeight = 200;  // a flat profile gets this much (its heights centred), at its scale
constexpr int kMaxPlotHeight = 1200; // a steep one is drawn narrower instead of taller
constexpr int kRanks = 9;

const std::uint32_t kBackground = render::pack_rgba(24, 26, 32), kGridColour = render::pack_rgba(60, 64, 72),
                    kAxisColour = render::pack_rgba(150, 150, 160), kTextColour = render::pack_rgba(215, 217, 225);

// 1, 2 or 5 times a power of ten, so that `span` holds about `lines` steps (at least one).
double round_step(double span, double lines) {
    const double raw = span / std::max(1.0, lines), p = std::pow(10.0, std::floor(std::log10(raw)));
    for (const double m : {1.0, 2.0, 5.0}) {
        if (m * p >= raw) return m * p;
    }
    return 10 * p;
}

// A tick value with as many decimals as its step needs ("850", "2.5", "0.05").
std::string tick_text(double value, double step) {
    const int decimals = step >= 1 ? 0 : static_cast<int>(std::ceil(-std::log10(step) - 1e-9));
    if (std::abs(value) < step * 1e-6) value = 0;  // no "-0"
    char text[48];
    std::snprintf(text, sizeof text, "%.*f", decimals, value);
    return text;
}

struct Layout {
    int width = 0, height = 0;                        // the image
    int left = kMargin, right = kMargin, top = kMargin, bottom = kMargin;  // the margins around the plot
    double length = 1, z_min = 0, z_max = 1, px_per_d = 1, px_per_z = 1;
    int px(double d) const { return left + static_cast<int>(std::lround(d * px_per_d)); }
    int py(double z) const { return height - bottom - static_cast<int>(std::lround((z - z_min) * px_per_z)); }
    int plot_width() const { return width - left - right; }
    int plot_height() const { return height - top - bottom; }
};

struct HeightRange {
    double lo = 0, hi = 1;
};

HeightRange heights_of(const Profile& profile) {
    HeightRange r{INFINITY, -INFINITY};
    for (const auto& p : profile.points) r.lo = std::min(r.lo, p.z), r.hi = std::max(r.hi, p.z);
    if (!(r.lo <= r.hi)) r = {0, 1};
    return r;
}

// The heights' range (a tenth more on each side) filling the plot of a width x height image.
void fill_layout(Layout& l, const HeightRange& h, int width, int height) {
    const double pad = std::max(0.5, (h.hi - h.lo) / 10);
    l.width = width, l.height = height, l.z_min = h.lo - pad, l.z_max = h.hi + pad;
    l.px_per_d = std::max(1, l.plot_width()) / l.length;
    l.px_per_z = std::max(1, l.plot_height()) / (l.z_max - l.z_min);
}

// The scales of true (or exaggerated) scale: as wide as the options allow, as tall as the heights
// need, within kMinPlotHeight - kMaxPlotHeight; the margins `l` has are kept.
void scale_layout(Layout& l, const HeightRange& h, const ProfileImageOptions& o) {
    const double pad = std::max((h.hi - h.lo) / 20, 1e-6);
    const double lo = h.lo - pad, hi = h.hi + pad;
    const double z_per_d = o.exaggeration * o.z_to_metres / o.distance_to_metres;  // z pixels per d pixel
    l.px_per_d = std::max(1, o.width - l.left - l.right) / l.length;
    l.px_per_z = l.px_per_d * z_per_d;
    double plot_h = (hi - lo) * l.px_per_z;
    if (plot_h > kMaxPlotHeight) {  // steep: the plot narrower, the scale kept
        l.px_per_z = kMaxPlotHeight / (hi - lo);
        l.px_per_d = l.px_per_z / z_per_d;
        plot_h = kMaxPlotHeight;
    }
    const double shown = std::max(plot_h, double(kMinPlotHeight)) / l.px_per_z;  // the z range the plot shows
    l.z_min = (lo + hi) / 2 - shown / 2, l.z_max = l.z_min + shown;
    l.width = l.left + static_cast<int>(std::lround(l.length * l.px_per_d)) + l.right;
    l.height = l.top + static_cast<int>(std::lround(shown * l.px_per_z)) + l.bottom;
}

void fit_layout(Layout& l, const HeightRange& h, const ProfileImageOptions& o) {
    if (o.height > 0) fill_layout(l, h, o.width, o.height);
    else scale_layout(l, h, o);
}

struct Steps {
    double d = 1, z = 1;
};

// Grid lines about every 140 pixels along, 70 up.
Steps steps_of(const Layout& l) {
    return {round_step(l.length, l.plot_width() / 140.0), round_step(l.z_max - l.z_min, l.plot_height() / 70.0)};
}

// The widest height label at these steps.
int z_label_width(const Layout& l, double z_step) {
    int widest = 0;
    for (double z = std::ceil(l.z_min / z_step) * z_step; z <= l.z_max; z += z_step) {
        widest = std::max(widest, render::text_width(tick_text(z, z_step), kTextScale));
    }
    return widest;
}

// The image's layout. Labelled: margins for the caption (top), the distance labels and title
// (bottom), the height labels and title (left) and half a distance label (right); the left margin
// follows the widest height label, so the layout is made again while that widens it.
Layout layout_of(const HeightRange& h, double length, const ProfileImageOptions& o) {
    const int text_h = render::text_height(kTextScale);
    Layout l;
    l.length = length;
    if (o.labels) {
        l.top = text_h + 2 * kGap;
        l.bottom = kTick + kGap + text_h + kGap + text_h + kGap;
        l.right = kMargin + render::text_width(tick_text(length, round_step(length, 10)), kTextScale) / 2;
        l.left = kGap + text_h + kGap + render::text_width("0000", kTextScale) + kGap + kTick;
    }
    for (int pass = 0; pass < 3; ++pass) {
        fit_layout(l, h, o);
        if (!o.labels) break;
        const int left = kGap + text_h + kGap + z_label_width(l, steps_of(l).z) + kGap + kTick;
        if (left <= l.left) break;
        l.left = left;
    }
    return l;
}

void put(render::RgbaImage& image, int x, int y, std::uint32_t colour) {
    if (x < 0 || y < 0 || x >= image.width || y >= image.height) return;
    image.pixels[std::size_t(y) * image.width + x] = colour;
}

void draw_grid(render::RgbaImage& image, const Layout& l, const Steps& s) {
    const int bottom = l.height - l.bottom, right = l.px(l.length);
    for (double d = 0; d <= l.length + 1e-9; d += s.d) {
        for (int y = l.top; y < bottom; ++y) put(image, l.px(d), y, d == 0 ? kAxisColour : kGridColour);
    }
    for (double z = std::ceil(l.z_min / s.z) * s.z; z <= l.z_max; z += s.z) {
        for (int x = l.left; x <= right; ++x) put(image, x, l.py(z), kGridColour);
    }
    for (int x = l.left; x <= right; ++x) put(image, x, bottom, kAxisColour);
}

// Tick marks and values on both axes, the axes' titles and, above the plot, its vertical scale.
void draw_labels(render::RgbaImage& image, const Layout& l, const Steps& s, const ProfileImageOptions& o,
                 double exaggeration) {
    const int text_h = render::text_height(kTextScale), bottom = l.height - l.bottom;
    for (double d = 0; d <= l.length + 1e-9; d += s.d) {
        const int x = l.px(d);
        for (int y = bottom; y < bottom + kTick; ++y) put(image, x, y, kAxisColour);
        const std::string t = tick_text(d, s.d);
        render::draw_text(image, x - render::text_width(t, kTextScale) / 2, bottom + kTick + kGap, t, kTextColour,
                          kTextScale);
    }
    for (double z = std::ceil(l.z_min / s.z) * s.z; z <= l.z_max; z += s.z) {
        const int y = l.py(z);
        for (int x = l.left - kTick; x < l.left; ++x) put(image, x, y, kAxisColour);
        const std::string t = tick_text(z, s.z);
        render::draw_text(image, l.left - kTick - kGap - render::text_width(t, kTextScale), y - text_h / 2, t,
                          kTextColour, kTextScale);
    }
    const std::string du = o.distance_unit.empty() ? "units" : o.distance_unit;
    const std::string zu = o.z_unit.empty() ? "units" : o.z_unit;
    const std::string along = "distance along the line (" + du + ")", up = "height (" + zu + ")";
    render::draw_text(image, l.left + (l.plot_width() - render::text_width(along, kTextScale)) / 2,
                      l.height - kGap - text_h, along, kTextColour, kTextScale);
    render::draw_text_up(image, kGap, l.top + (l.plot_height() + render::text_width(up, kTextScale)) / 2, up,
                         kTextColour, kTextScale);
    char caption[96];
    if (std::abs(exaggeration - 1) < 1e-3) std::snprintf(caption, sizeof caption, "true scale (heights 1:1)");
    else std::snprintf(caption, sizeof caption, "heights exaggerated %.3gx", exaggeration);
    render::draw_text(image, l.left, kGap, caption, kTextColour, kTextScale);
}

// The points' indices in drawing order: by profile_draw_rank, in file order within a rank.
std::vector<std::size_t> drawing_order(const Profile& profile) {
    std::array<std::size_t, kRanks + 1> start{};
    for (const auto& p : profile.points) ++start[static_cast<std::size_t>(profile_draw_rank(p.classification)) + 1];
    for (int r = 0; r < kRanks; ++r) start[r + 1] += start[r];
    std::vector<std::size_t> order(profile.points.size());
    for (std::size_t i = 0; i < profile.points.size(); ++i) {
        order[start[static_cast<std::size_t>(profile_draw_rank(profile.points[i].classification))]++] = i;
    }
    return order;
}

void draw_points(render::RgbaImage& image, const Layout& l, const Profile& profile, ProfileColours colours,
                 double ramp_min, double ramp_max) {
    if (!(ramp_max > ramp_min)) ramp_min = l.z_min, ramp_max = l.z_max;
    for (const std::size_t i : drawing_order(profile)) {
        const auto& p = profile.points[i];
        const std::uint32_t c =
            colours == ProfileColours::Elevation
                ? render::elevation_ramp(static_cast<float>((p.z - ramp_min) / (ramp_max - ramp_min)))
                : render::classification_colour(p.classification);
        const int x = l.px(p.distance), y = l.py(p.z);
        put(image, x, y, c), put(image, x + 1, y, c), put(image, x, y + 1, c), put(image, x + 1, y + 1, c);
    }
}

render::RgbaImage blank(const Layout& l) {
    render::RgbaImage image{l.width, l.height, {}};
    image.pixels.assign(std::size_t(image.width) * image.height, kBackground);
    return image;
}

ProfileImageScale scale_of(const Layout& l, const Steps& s, double z_to_metres, double distance_to_metres) {
    return {l.z_min, l.z_max, s.d, s.z, l.px_per_d, l.px_per_z,
            (l.px_per_z / z_to_metres) / (l.px_per_d / distance_to_metres)};
}

const char* unit_label(double to_metres) {
    if (std::abs(to_metres - 1.0) < 1e-12) return "m";
    if (std::abs(to_metres - las::kFootMetres) < 1e-12) return "ft";
    if (std::abs(to_metres - las::kUsSurveyFootMetres) < 1e-12) return "US ft";
    return "units";
}

}  // namespace

ProfileImageOptions profile_png_options(const dataset::Frame& frame, double exaggeration) {
    ProfileImageOptions o;
    o.exaggeration = exaggeration;
    o.distance_to_metres = frame.xy_to_metres, o.z_to_metres = frame.z_to_metres;
    o.distance_unit = unit_label(frame.xy_to_metres), o.z_unit = unit_label(frame.z_to_metres);
    return o;
}

int profile_draw_rank(std::uint8_t classification) {
    switch (classification) {
        case 7: case 18: return 0;          // noise, low and high
        case 5: return 1;                   // high vegetation
        case 4: return 2;                   // medium vegetation
        case 3: return 3;                   // low vegetation
        case 0: case 1: return 4;           // never classified, unclassified
        case 6: return 6;                   // building
        case 9: return 7;                   // water
        case 2: return 8;                   // ground, on top
        default: return 5;                  // the other classes
    }
}

render::RgbaImage profile_image(const Profile& profile, const Corridor& corridor, const ProfileImageOptions& o,
                                ProfileImageScale* scale) {
    if (!(o.exaggeration > 0) || !std::isfinite(o.exaggeration)) {
        throw Error::in_stage("profile", "the vertical exaggeration must be a positive number");
    }
    const double length = std::max(corridor.length(), 1e-9);
    const HeightRange h = heights_of(profile);
    const Layout l = layout_of(h, length, o);
    const Steps s = o.labels ? steps_of(l) : Steps{round_step(l.length, 10), round_step(l.z_max - l.z_min, 6)};
    render::RgbaImage image = blank(l);
    draw_grid(image, l, s);
    draw_points(image, l, profile, o.colours, o.ramp_min, o.ramp_max);
    const ProfileImageScale sc = scale_of(l, s, o.z_to_metres, o.distance_to_metres);
    if (o.labels) draw_labels(image, l, s, o, sc.exaggeration);
    if (scale) *scale = sc;
    return image;
}

render::RgbaImage profile_image(const Profile& profile, const Corridor& corridor, int width, int height,
                                ProfileImageScale* scale, ProfileColours colours, double ramp_min, double ramp_max) {
    ProfileImageOptions o;
    o.width = width, o.height = height, o.labels = false;
    o.colours = colours, o.ramp_min = ramp_min, o.ramp_max = ramp_max;
    return profile_image(profile, corridor, o, scale);
}

}  // namespace lidarscout::pipelines
