// Picking on heightmaps: the surface height between texel centres and in holes, a ray from above
// hitting a tilted plane where the pixel shows it, an oblique ray stopping at the first rise, and
// a click choosing a point drawn on the surface over the surface, but not a point hidden by it.
#include "viewer/surface_pick.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "core/thread_pool.hpp"
#include "viewer/point_lod.hpp"
#include "viewer/cameras.hpp"

namespace lidarscout::viewer {
namespace {

constexpr double kOriginX = 5000, kOriginY = 7000;

// 64 x 64 texels of 10 m from (kOriginX, kOriginY), heights from fn(x, y) at the texel centres.
template <typename Fn>
std::shared_ptr<const PatchHeightmap> heightmap(Fn&& fn) {
    PatchHeightmap h;
    h.origin_x = kOriginX, h.origin_y = kOriginY, h.texel_m = 10, h.size = 64;
    h.heights.resize(64 * 64);
    for (int row = 0; row < 64; ++row) {
        for (int col = 0; col < 64; ++col) {
            const double x = kOriginX + (col + 0.5) * 10, y = kOriginY + (row + 0.5) * 10;
            h.heights[row * 64 + col] = static_cast<float>(fn(x, y));
        }
    }
    return share(std::move(h));
}

double plane(double x, double y) { return 200 + 0.05 * (x - kOriginX) - 0.02 * (y - kOriginY); }

using test::looking_down;

TEST(SurfacePick, HeightIsBilinearBetweenTexelCentresAndNaNInHolesAndOutside) {
    auto h = std::const_pointer_cast<PatchHeightmap>(heightmap(plane));
    const double x = kOriginX + 123.4, y = kOriginY + 456.7;
    EXPECT_NEAR(surface_height(*h, x, y), plane(x, y), 1e-3);
    EXPECT_NEAR(surface_height(*h, kOriginX + 2, kOriginY + 638), plane(kOriginX + 2, kOriginY + 638), 1e-3);  // edges
    EXPECT_TRUE(std::isnan(surface_height(*h, kOriginX - 1, kOriginY + 10)));
    EXPECT_TRUE(std::isnan(surface_height(*h, kOriginX + 10, kOriginY + 641)));
    h->heights[10 * 64 + 20] = NAN;  // the texel of (205, 105)
    EXPECT_TRUE(std::isnan(surface_height(*h, kOriginX + 204, kOriginY + 104)));
    EXPECT_FALSE(std::isnan(surface_height(*h, kOriginX + 300, kOriginY + 300)));
}

TEST(SurfacePick, RayFromAboveMeetsThePlaneWhereThePixelShowsIt) {
    SceneSnapshot s;
    s.heightmaps = {heightmap(plane)};
    const auto camera = looking_down(kOriginX + 320, kOriginY + 320, 2000);
    for (const auto& [x, y] : {std::pair{kOriginX + 320.0, kOriginY + 320.0}, {kOriginX + 101.0, kOriginY + 555.0}}) {
        const auto pixel = camera.project(x, y, plane(x, y));
        ASSERT_TRUE(pixel);
        const auto hit = pick_surface(s, camera, pixel->x, pixel->y);
        ASSERT_TRUE(hit);
        EXPECT_TRUE(hit->surface);
        EXPECT_NEAR(hit->x, x, 0.05);
        EXPECT_NEAR(hit->y, y, 0.05);
        EXPECT_NEAR(hit->z, plane(x, y), 0.01);
        EXPECT_NEAR(hit->depth, 2000 - plane(x, y), 0.05);
    }
    EXPECT_FALSE(pick_surface(s, camera, 0, 0));  // a corner of the image: beyond the patch
}

TEST(SurfacePick, ObliqueRayStopsAtTheFirstRise) {
    SceneSnapshot s;  // flat at 0 m, a 50 m step up from x = 320 m (texel centres 315 and 325 m)
    s.heightmaps = {heightmap([](double x, double) { return x - kOriginX > 320 ? 50.0 : 0.0; })};
    render::Camera c;
    c.x = kOriginX - 100, c.y = kOriginY + 320, c.z = 30;
    c.yaw_deg = 90, c.pitch_deg = -2;  // looking east, slightly down
    c.near_m = 0.5, c.far_m = 1e5;
    const auto hit = pick_surface(s, c, c.width / 2.0, c.height / 2.0);
    ASSERT_TRUE(hit);
    EXPECT_GT(hit->x, kOriginX + 315);
    EXPECT_LT(hit->x, kOriginX + 325);
    EXPECT_NEAR(hit->y, kOriginY + 320, 0.01);
    const double ray_z = 30 - std::tan(2 * M_PI / 180) * (hit->x - c.x);
    EXPECT_NEAR(hit->z, ray_z, 0.01);
    EXPECT_NEAR(hit->z, surface_height(*s.heightmaps[0], hit->x, hit->y), 1e-3);
}

TEST(SurfacePick, APointOnTheSurfaceWinsAndOneHiddenBehindItDoesNot) {
    SceneSnapshot s;
    s.heightmaps = {heightmap(plane)};
    PointSet set;  // one point on the surface at (200, 200), one 150 m under it at (400, 400)
    set.origin_x = kOriginX, set.origin_y = kOriginY, set.origin_z = 0;
    render::PointAttr a;
    a.dx = 200, a.dy = 200, a.dz = static_cast<float>(plane(kOriginX + 200, kOriginY + 200)), a.classification = 2;
    render::PointAttr b = a;
    b.dx = 400, b.dy = 400, b.dz = static_cast<float>(plane(kOriginX + 400, kOriginY + 400) - 150);
    set.points = {a, b};
    ThreadPool pool(1);
    s.full_points = build_lod_blocks(set, 0, 80, pool);
    const auto camera = looking_down(kOriginX + 320, kOriginY + 320, 2000);
    const auto on = camera.project(kOriginX + 200, kOriginY + 200, a.dz);
    const auto under = camera.project(kOriginX + 400, kOriginY + 400, b.dz);
    ASSERT_TRUE(on && under);
    const auto p = pick(s, camera, on->x, on->y);
    ASSERT_TRUE(p);
    EXPECT_FALSE(p->surface);
    EXPECT_EQ(p->classification, 2);
    const auto q = pick(s, camera, under->x, under->y);
    ASSERT_TRUE(q);
    EXPECT_TRUE(q->surface);
    EXPECT_NEAR(q->z, plane(q->x, q->y), 0.01);
}

}  // namespace
}  // namespace lidarscout::viewer
