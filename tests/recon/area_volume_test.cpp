// Area and volume on synthetic shapes with known answers: a 10 x 10 x 2 m box on flat ground
// (cut 200 m3), a 1 m deep pit (fill 100 m3), a horizontal base above flat ground (fill), a tilted
// plane whose vertices carry it (no cut, no fill; its surface area 1/cos of its slope), a cone
// (pi r2 h / 3 within 2%), holes in the points filled from their neighbours, and the refusals.
#include "recon/area_volume.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <numbers>
#include <vector>

#include "core/error.hpp"

namespace lidarscout::recon {
namespace {

// Points every `step` m over [0, side)^2 (at cell centres when step divides the cell), z = f(x, y).
std::vector<Point3> points_on(double side, double step, const std::function<double(double, double)>& f) {
    std::vector<Point3> out;
    for (double y = step / 2; y < side; y += step)
        for (double x = step / 2; x < side; x += step) out.push_back({x, y, f(x, y)});
    return out;
}

std::vector<Point3> square(double x0, double y0, double x1, double y1, double z = 0) {
    return {{x0, y0, z}, {x1, y0, z}, {x1, y1, z}, {x0, y1, z}};
}

TEST(AreaVolume, ABoxOnFlatGroundIsItsVolume) {
    const auto points = points_on(40, 0.5, [](double x, double y) {
        return (x > 15 && x < 25 && y > 15 && y < 25) ? 2.0 : 0.0;
    });
    const auto a = measure_area_volume(square(10, 10, 30, 30), points, {.cell_m = 1.0});
    EXPECT_DOUBLE_EQ(a.horizontal_area_m2, 400);
    EXPECT_NEAR(a.cut_m3, 200, 1e-6);
    EXPECT_NEAR(a.fill_m3, 0, 1e-6);
    EXPECT_EQ(a.cells, 400u);
    EXPECT_EQ(a.points, 1600u);
    EXPECT_EQ(a.cells_filled, 0u);
    EXPECT_GT(a.surface_area_m2, 400);  // the box's sides
    EXPECT_NE(area_volume_summary(a).find("cut 200.0 m3"), std::string::npos) << area_volume_summary(a);
}

TEST(AreaVolume, APitIsFillAndAHigherBaseTurnsGroundIntoFill) {
    const auto pit = points_on(40, 0.5, [](double x, double y) {
        return (x > 15 && x < 25 && y > 15 && y < 25) ? -1.0 : 0.0;
    });
    const auto a = measure_area_volume(square(10, 10, 30, 30), pit, {.cell_m = 1.0});
    EXPECT_NEAR(a.fill_m3, 100, 1e-6);
    EXPECT_NEAR(a.cut_m3, 0, 1e-6);
    const auto flat = points_on(40, 0.5, [](double, double) { return 0.0; });
    const auto b = measure_area_volume(square(10, 10, 30, 30), flat, {.cell_m = 1.0, .base_height = 1.5});
    EXPECT_NEAR(b.fill_m3, 600, 1e-6);
    EXPECT_NE(b.base.find("height 1.50 m"), std::string::npos);
}

TEST(AreaVolume, ATiltedPlaneCarriedByItsVerticesHasNoVolume) {
    const auto z = [](double x, double y) { return 100 + 0.1 * x - 0.05 * y; };
    const auto points = points_on(40, 0.5, z);
    std::vector<Point3> polygon = square(10, 10, 30, 30);
    for (auto& v : polygon) v[2] = z(v[0], v[1]);
    const auto a = measure_area_volume(polygon, points, {.cell_m = 1.0});
    EXPECT_NEAR(a.cut_m3, 0, 1e-3);
    EXPECT_NEAR(a.fill_m3, 0, 1e-3);
    EXPECT_NEAR(a.surface_area_m2, 400 * std::sqrt(1 + 0.01 + 0.0025), 1e-3);
    EXPECT_NEAR(a.base_plane[1], 0.1, 1e-12);
    EXPECT_NEAR(a.base_plane[2], -0.05, 1e-12);
}

TEST(AreaVolume, AConeIsAThirdOfItsCylinder) {
    const double r = 8, h = 6;
    const auto points = points_on(40, 0.25, [&](double x, double y) {
        return std::max(0.0, h * (1 - std::hypot(x - 20, y - 20) / r));
    });
    // A triangle's worth of sides is no square: an octagon around the cone.
    std::vector<Point3> octagon;
    for (int k = 0; k < 8; ++k) {
        const double t = k * std::numbers::pi / 4;
        octagon.push_back({20 + 12 * std::cos(t), 20 + 12 * std::sin(t), 0});
    }
    const auto a = measure_area_volume(octagon, points);  // the cell from the spacing
    EXPECT_NEAR(a.cut_m3, std::numbers::pi * r * r * h / 3, 0.02 * std::numbers::pi * r * r * h / 3);
    EXPECT_NEAR(a.horizontal_area_m2, 2 * std::sqrt(2.0) * 144, 1e-9);  // a regular octagon of radius 12
    EXPECT_NEAR(a.cell_m, 0.5, 0.005);                                    // twice the spacing
}

TEST(AreaVolume, HolesInThePointsAreFilledFromTheirNeighbours) {
    auto points = points_on(40, 0.5, [](double, double) { return 3.0; });
    std::erase_if(points, [](const Point3& p) { return p[0] > 18 && p[0] < 22 && p[1] > 18 && p[1] < 22; });
    const auto a = measure_area_volume(square(10, 10, 30, 30, 0), points, {.cell_m = 1.0});
    EXPECT_EQ(a.cells_filled, 16u);
    EXPECT_EQ(a.cells_unmeasured, 0u);
    EXPECT_NEAR(a.cut_m3, 1200, 1e-6);  // the hole at the height around it
}

TEST(AreaVolume, WhatCannotBeMeasuredIsRefused) {
    const auto points = points_on(40, 0.5, [](double, double) { return 0.0; });
    const auto two = square(10, 10, 30, 30);
    EXPECT_THROW(measure_area_volume(std::span(two).subspan(0, 2), points), Error);
    const std::vector<Point3> line = {{0, 0, 0}, {10, 10, 0}, {20, 20, 0}};
    EXPECT_THROW(measure_area_volume(line, points), Error);  // no area
    const std::vector<Point3> far = square(1000, 1000, 1010, 1010);
    EXPECT_THROW(measure_area_volume(far, points, {.cell_m = 1.0}), Error);  // no point inside
    EXPECT_THROW(measure_area_volume(square(0, 0, 40, 40), points, {.cell_m = 0.001}), Error);  // 1.6e9 cells
    const auto huge = measure_area_volume(square(-1e4, -1e4, 1e4, 1e4), points);  // 400 km2: cells grow
    EXPECT_GE(huge.cell_m, 10.0);
    EXPECT_GT(huge.cells_unmeasured, huge.cells / 2);  // far from any point: left out, not invented
    std::vector<Point3> collinear_base = {{10, 10, 0}, {30, 10, 0}, {20, 10.000000001, 0}};
    EXPECT_THROW(measure_area_volume(collinear_base, points, {.cell_m = 1.0}), Error);
}

}  // namespace
}  // namespace lidarscout::recon
