// The viewer's profile tool without a window: `--profile` text parsed and refused, the profile click
// tool's two ends, the corridor from picked points in a feet CRS, the lowest heights along a line;
// a ProfileJob on a real Kentucky tile reads what read_profile reads (same points, same filter),
// draws an image and the ground line, draws again in another look, and ends when closed mid-read.
#include "viewer/profile_tool.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <tuple>

#include "core/error.hpp"
#include "core/thread_pool.hpp"
#include "test_data.hpp"

namespace lidarscout::viewer {
namespace {

TEST(ViewerProfileTool, CorridorTextIsFiveNumbers) {
    const auto c = parse_corridor("5208145.5,3902993.25,5209000,3904000,6");
    EXPECT_EQ(c.x0, 5208145.5);
    EXPECT_EQ(c.y0, 3902993.25);
    EXPECT_EQ(c.x1, 5209000);
    EXPECT_EQ(c.y1, 3904000);
    EXPECT_EQ(c.width, 6);
    EXPECT_EQ(parse_corridor("-1.5,0,1e3,0,0.25").x0, -1.5);
    for (const std::string bad : {"", "1,2,3,4", "1,2,3,4,5,6", "1,2,3,4,x", "1,2,,4,5", "1,2,3,4,0", "1,2,3,4,-2",
                                  "1,2,1,2,3", "1,2,3,4,nan", "1,2,3,4,5 "}) {
        EXPECT_THROW(parse_corridor(bad), Error) << bad;
    }
    try {
        parse_corridor("1,2,3,4");
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("--profile wants x0,y0,x1,y1,width"), std::string::npos) << e.what();
    }
}

TEST(ViewerProfileTool, TwoClicksGiveTheLineThenItStartsAgain) {
    PickedPoint a, b, c;
    a.x = 1, b.x = 2, c.x = 3;
    ClickState click;
    click.use(ClickTool::Profile);
    click.clicked(a);
    EXPECT_TRUE(click.from);
    EXPECT_FALSE(click.to);
    click.clicked(std::nullopt);  // a miss keeps the first end
    EXPECT_TRUE(click.from);
    click.clicked(b);
    ASSERT_TRUE(click.to);
    EXPECT_EQ(click.from->x, 1);
    EXPECT_EQ(click.to->x, 2);
    click.clicked(c);  // a new line
    EXPECT_EQ(click.from->x, 3);
    EXPECT_FALSE(click.to);
    click.use(ClickTool::Area);
    EXPECT_FALSE(click.from);
}

TEST(ViewerProfileTool, CorridorBetweenPickedPointsIsInTheCrsUnits) {
    dataset::Frame feet;
    feet.xy_to_metres = 1200.0 / 3937.0;
    PickedPoint a, b;
    a.x = 1000 * feet.xy_to_metres, a.y = 2000 * feet.xy_to_metres;
    b.x = 1300 * feet.xy_to_metres, b.y = 2400 * feet.xy_to_metres;
    const auto c = corridor_between(a, b, 6, feet);
    EXPECT_NEAR(c.x0, 1000, 1e-9);
    EXPECT_NEAR(c.y1, 2400, 1e-9);
    EXPECT_NEAR(c.length(), 500, 1e-9);
    EXPECT_EQ(c.width, 6);
}

TEST(ViewerProfileTool, LowestAlongFillsGapsFromTheNearestPiece) {
    std::vector<pipelines::ProfilePoint> points(4);
    points[0].distance = 1, points[0].z = 10;
    points[1].distance = 2, points[1].z = 7;   // same piece as the first: the lowest wins
    points[2].distance = 95, points[2].z = 20;
    points[3].distance = 100, points[3].z = 30;  // the end lands in the last piece
    const auto low = lowest_along(points, 100, 4);
    ASSERT_EQ(low.size(), 4u);
    EXPECT_EQ(low[0], 7);
    EXPECT_EQ(low[1], 7);   // empty: the piece before
    EXPECT_EQ(low[2], 20);  // empty: the piece after
    EXPECT_EQ(low[3], 20);
    EXPECT_TRUE(std::isnan(lowest_along({}, 100, 4)[2]));
}

class ViewerProfileJob : public ::testing::Test {
protected:
    void SetUp() override {
        ds = dataset::open_dataset({(test::surveys_dir() / "ky-woodford-county" / "5205000_3900000.laz").string()});
        ASSERT_EQ(ds.tiles.size(), 1u);
        const auto& h = ds.tiles[0].tile.header;
        corridor = {h.min[0] + 0.1 * (h.max[0] - h.min[0]), h.min[1] + 0.1 * (h.max[1] - h.min[1]),
                    h.min[0] + 0.9 * (h.max[0] - h.min[0]), h.min[1] + 0.8 * (h.max[1] - h.min[1]), 6.0};
    }
    static std::vector<std::tuple<double, double, double, int>> keys(const pipelines::Profile& p) {
        std::vector<std::tuple<double, double, double, int>> out;
        for (const auto& q : p.points) out.emplace_back(q.x, q.y, q.z, q.classification);
        std::sort(out.begin(), out.end());
        return out;
    }
    dataset::Dataset ds;
    pipelines::Corridor corridor;
};

TEST_F(ViewerProfileJob, ReadsWhatReadProfileReadsAndDrawsIt) {
    const PointFilter ground = PointFilter::parse("2", "", "");
    const auto expected = pipelines::read_profile(ds, corridor, ground, ThreadPool::shared());
    ASSERT_GT(expected.points.size(), 100u);
    ProfileLook look;
    look.width = 400, look.height = 150;
    ProfileJob job(ds, corridor, ground, look, 2);
    job.wait();
    const ProfileStatus st = job.status();
    EXPECT_TRUE(st.done);
    EXPECT_EQ(st.error, "");
    EXPECT_EQ(st.points, expected.points.size());
    EXPECT_EQ(st.read.points_read, ds.tiles[0].tile.header.point_count);
    EXPECT_EQ(st.read.tiles_done, 1u);
    EXPECT_EQ(st.read.tiles_total, 1u);
    const auto profile = job.profile();
    ASSERT_TRUE(profile);
    EXPECT_EQ(keys(*profile), keys(expected));
    std::uint64_t seen = 0;
    const auto image = job.image_since(seen);
    ASSERT_TRUE(image);
    EXPECT_EQ(image->width, 400);
    EXPECT_EQ(image->height, 150);
    EXPECT_FALSE(job.image_since(seen));  // nothing newer
    const auto line = job.line_heights();
    ASSERT_EQ(line.size(), ProfileJob::kLineBins);
    for (const double z : line) {
        EXPECT_GE(z, ds.tiles[0].tile.header.min[2]);
        EXPECT_LE(z, ds.tiles[0].tile.header.max[2]);
    }
    EXPECT_GT(job.scale().z_max, job.scale().z_min);
    look.colours = pipelines::ProfileColours::Elevation;  // drawn again, on the job's thread
    job.set_look(look);
    std::shared_ptr<const render::RgbaImage> again;
    while (!(again = job.image_since(seen))) std::this_thread::yield();
    EXPECT_NE(again->pixels, image->pixels);
}

TEST_F(ViewerProfileJob, ClosedWhileReadingItStops) {
    for (int k = 0; k < 3; ++k) {  // closed at once, and again and again: no hang, no crash
        ProfileJob job(ds, corridor, PointFilter(), ProfileLook{}, 2);
        if (k == 2) {
            while (job.status().read.points_read == 0 && !job.status().done) std::this_thread::yield();
        }
    }
    ProfileJob job(ds, corridor, PointFilter(), ProfileLook{}, 2);
    job.cancel();  // the read stops; the job is done (its profile whole, or none when it stopped early)
    job.wait();
    EXPECT_TRUE(job.status().done);
    EXPECT_EQ(job.status().error, "");
    if (!job.profile()) EXPECT_LT(job.status().read.points_read, ds.tiles[0].tile.header.point_count);
    std::atomic<bool> cancel{true};  // a read told to stop before it starts returns no point
    pipelines::ReadWatch watch;
    watch.cancel = &cancel;
    const auto p = pipelines::read_profile(ds, corridor, PointFilter(), ThreadPool::shared(), watch);
    EXPECT_TRUE(p.read.cancelled);
    EXPECT_EQ(p.points.size(), 0u);
    EXPECT_EQ(p.read.points_read, 0u);
}

TEST_F(ViewerProfileJob, ACorridorAwayFromTheDataIsEmptyNotAnError) {
    const pipelines::Corridor away{0, 0, 10, 10, 2};
    ProfileJob job(ds, away, PointFilter(), ProfileLook{}, 1);
    job.wait();
    EXPECT_EQ(job.status().error, "");
    EXPECT_EQ(job.status().points, 0u);
    EXPECT_EQ(job.status().read.tiles_total, 0u);
    ASSERT_TRUE(job.profile());
}

}  // namespace
}  // namespace lidarscout::viewer
