// Overlay lines: projection of segment ends, clipping to the image, a DDA line walk; markers.
#include "viewer/app/overlay.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <vector>

#include "render/framebuffer.hpp"
#include "viewer/visibility.hpp"

namespace lidarscout::viewer::app {
namespace {

void plot_line(render::RgbaImage& image, double x0, double y0, double x1, double y1, std::uint32_t rgba) {
    // Clip the parameter range to the image box (Liang-Barsky).
    double t0 = 0, t1 = 1;
    const double dx = x1 - x0, dy = y1 - y0;
    const double p[4] = {-dx, dx, -dy, dy};
    const double q[4] = {x0, image.width - 1 - x0, y0, image.height - 1 - y0};
    for (int i = 0; i < 4; ++i) {
        if (p[i] == 0) {
            if (q[i] < 0) return;
            continue;
        }
        const double t = q[i] / p[i];
        if (p[i] < 0) t0 = std::max(t0, t);
        else t1 = std::min(t1, t);
    }
    if (t0 > t1) return;
    const double ax = x0 + t0 * dx, ay = y0 + t0 * dy, bx = x0 + t1 * dx, by = y0 + t1 * dy;
    const int steps = static_cast<int>(std::ceil(std::max(std::abs(bx - ax), std::abs(by - ay)))) + 1;
    // Rounded by adding a half and truncating (the clipped ends lie in the image: at or above zero), not by a call
    // to lround per pixel: a country's 152,100 footprints are millions of pixels.
    const double step_x = (bx - ax) / steps, step_y = (by - ay) / steps;
    for (int s = 0; s <= steps; ++s) {
        const int x = static_cast<int>(ax + s * step_x + 0.5), y = static_cast<int>(ay + s * step_y + 0.5);
        if (x >= 0 && y >= 0 && x < image.width && y < image.height) {
            image.pixels[static_cast<std::size_t>(y) * image.width + x] = rgba;
        }
    }
}

}  // namespace

void draw_segment(render::RgbaImage& image, const render::Camera& camera, double x0, double y0, double z0, double x1,
                  double y1, double z1, std::uint32_t rgba) {
    const auto a = camera.project(x0, y0, z0), b = camera.project(x1, y1, z1);
    if (!a || !b) return;
    plot_line(image, a->x, a->y, b->x, b->y, rgba);
}

namespace {

void draw_outline(render::RgbaImage& image, const render::Camera& camera, const dataset::Bounds& b,
                  std::uint32_t rgba) {
    if (!box_in_view(camera, b)) return;
    const double z = b.min_z;
    // Each corner projected once (a side whose end is not in front of the camera is not drawn).
    const std::array<std::optional<render::ScreenPoint>, 4> corner = {
        camera.project(b.min_x, b.min_y, z), camera.project(b.max_x, b.min_y, z),
        camera.project(b.max_x, b.max_y, z), camera.project(b.min_x, b.max_y, z)};
    for (std::size_t k = 0; k < corner.size(); ++k) {
        const auto& a = corner[k];
        const auto& e = corner[(k + 1) % corner.size()];
        if (a && e) plot_line(image, a->x, a->y, e->x, e->y, rgba);
    }
}

}  // namespace

void draw_tile_boxes(render::RgbaImage& image, const render::Camera& camera, const dataset::Dataset& dataset,
                     const dataset::TileIndex& places, std::uint32_t rgba, std::optional<std::uint32_t> selected) {
    places.visit([&](const dataset::Bounds& box) { return box_in_view(camera, box); },
                 [&](std::uint32_t i) {
                     draw_outline(image, camera, dataset.bounds(i),
                                  selected == i ? render::pack_rgba(255, 255, 255) : rgba);
                 });
}

void draw_footprints(render::RgbaImage& image, const render::Camera& camera, std::span<const dataset::Bounds> boxes,
                     std::uint32_t rgba) {
    for (const auto& b : boxes) draw_outline(image, camera, b, rgba);
}

void draw_marker(render::RgbaImage& image, const render::Camera& camera, double x, double y, double z,
                 std::uint32_t rgba) {
    const auto p = camera.project(x, y, z);
    if (!p) return;
    constexpr double kArm = 6;
    plot_line(image, p->x - kArm, p->y, p->x + kArm, p->y, rgba);
    plot_line(image, p->x, p->y - kArm, p->x, p->y + kArm, rgba);
}

void draw_click_overlay(render::RgbaImage& image, const render::Camera& camera, const ClickState& click) {
    const std::uint32_t marker = render::pack_rgba(255, 60, 200);
    if (click.from && click.to) {
        draw_segment(image, camera, click.from->x, click.from->y, click.from->z, click.to->x, click.to->y, click.to->z,
                     render::pack_rgba(255, 255, 255));
    }
    for (const auto* p : {&click.picked, &click.from, &click.to}) {
        if (*p) draw_marker(image, camera, (*p)->x, (*p)->y, (*p)->z, marker);
    }
    const auto& ring = click.polygon;  // the area tool's outline, closed once it has three vertices
    for (std::size_t k = 0; k < ring.size(); ++k) {
        draw_marker(image, camera, ring[k].x, ring[k].y, ring[k].z, marker);
        const auto& next = ring[(k + 1) % ring.size()];
        if (k + 1 < ring.size() || ring.size() >= 3) {
            draw_segment(image, camera, ring[k].x, ring[k].y, ring[k].z, next.x, next.y, next.z,
                         render::pack_rgba(120, 220, 255));
        }
    }
}

void draw_corridor(render::RgbaImage& image, const render::Camera& camera, const std::array<double, 4>& line,
                   double half_width, std::span<const double> heights, double z, std::uint32_t rgba) {
    const double dx = line[2] - line[0], dy = line[3] - line[1], length = std::hypot(dx, dy);
    if (!(length > 0)) return;
    const double nx = -dy / length * half_width, ny = dx / length * half_width;  // across the line
    // Vertices at the ends and the middle of every piece, each at its piece's height.
    std::vector<std::array<double, 2>> along;  // {t, z}
    const std::size_t n = heights.size();
    along.push_back({0.0, n ? heights[0] : z});
    for (std::size_t k = 0; k < n; ++k) along.push_back({(k + 0.5) / n, heights[k]});
    along.push_back({1.0, n ? heights[n - 1] : z});
    const auto at = [&](const std::array<double, 2>& v, double side) {
        return std::array<double, 3>{line[0] + v[0] * dx + side * nx, line[1] + v[0] * dy + side * ny, v[1]};
    };
    for (const double side : {-1.0, 0.0, 1.0}) {
        for (std::size_t k = 0; k + 1 < along.size(); ++k) {
            const auto a = at(along[k], side), b = at(along[k + 1], side);
            draw_segment(image, camera, a[0], a[1], a[2], b[0], b[1], b[2], rgba);
        }
    }
    for (const auto& end : {along.front(), along.back()}) {
        const auto a = at(end, -1), b = at(end, 1);
        draw_segment(image, camera, a[0], a[1], a[2], b[0], b[1], b[2], rgba);
    }
}

}  // namespace lidarscout::viewer::app
