// pipelines::read_profile: the points of a corridor across a real Kentucky tile equal a brute-force
// pass over every point of the tile (perpendicular distance within half the width, along the line
// within its length); the CSV holds them with a header line; the image is drawn at its size.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <string>
#include <tuple>
#include <vector>

#include "core/thread_pool.hpp"
#include "dataset/dataset.hpp"
#include "dataset/point_reader.hpp"
#include "io/file.hpp"
#include "pipelines/profile.hpp"
#include "pipelines/profile_image.hpp"
#include "temp_dir_fixture.hpp"
#include "test_data.hpp"

namespace lidarscout::pipelines {
namespace {

using Key = std::tuple<double, double, double, int>;  // x, y, z, class

class ProfileRead : public test::TempDirTest {
protected:
    void SetUp() override {
        TempDirTest::SetUp();
        ds = dataset::open_dataset({(test::surveys_dir() / "ky-woodford-county" / "5205000_3900000.laz").string()});
        ASSERT_EQ(ds.tiles.size(), 1u);
        const auto& h = ds.tiles[0].tile.header;
        // A diagonal from 10% to 90% of the tile's box.
        corridor = {h.min[0] + 0.1 * (h.max[0] - h.min[0]), h.min[1] + 0.1 * (h.max[1] - h.min[1]),
                    h.min[0] + 0.9 * (h.max[0] - h.min[0]), h.min[1] + 0.8 * (h.max[1] - h.min[1]), 6.0};
    }

    // Every point of the tile in the corridor, found without the region reader: the corridor's own
    // definition, written out again, on the decoded file coordinates (the CRS's units).
    std::vector<Key> brute_force(std::uint8_t only_class) const {
        const auto& tile = ds.tiles[0].tile;
        const auto& f = las::point_format_info(tile.header.point_format);
        const double dx = corridor.x1 - corridor.x0, dy = corridor.y1 - corridor.y0, len = std::hypot(dx, dy);
        std::vector<Key> out;
        const std::size_t n = tile.header.record_length;
        dataset::for_each_record_batch(io::File::open(tile.path()), tile, ThreadPool::shared(),
                                       [&](std::uint64_t, std::span<const std::uint8_t> records) {
            for (std::size_t k = 0; k + n <= records.size(); k += n) {
                const auto p = las::decode_point(records.subspan(k, n), f, tile.header);
                const double along = ((p.x - corridor.x0) * dx + (p.y - corridor.y0) * dy) / len;
                const double across = (dx * (p.y - corridor.y0) - dy * (p.x - corridor.x0)) / len;
                if (along < 0 || along > len || std::abs(across) > corridor.width / 2) continue;
                if (only_class != 255 && p.classification != only_class) continue;
                out.emplace_back(p.x, p.y, p.z, p.classification);
            }
        });
        std::sort(out.begin(), out.end());
        return out;
    }

    static std::vector<Key> keys(const Profile& p) {
        std::vector<Key> out;
        for (const auto& q : p.points) out.emplace_back(q.x, q.y, q.z, q.classification);
        std::sort(out.begin(), out.end());
        return out;
    }

    dataset::Dataset ds;
    Corridor corridor;
};

TEST_F(ProfileRead, PointsEqualABruteForceCorridorFilter) {
    const Profile p = read_profile(ds, corridor, PointFilter(), ThreadPool::shared());
    const auto expected = brute_force(255);
    EXPECT_GT(expected.size(), 1000u);
    EXPECT_EQ(p.points.size(), expected.size());
    EXPECT_EQ(keys(p), expected);
    EXPECT_EQ(p.read.points_read, ds.tiles[0].tile.header.point_count);
    for (const auto& q : p.points) {
        EXPECT_GE(q.distance, 0);
        EXPECT_LE(q.distance, corridor.length());
    }
    EXPECT_GE(p.seconds_to_first_points, 0);

    const Profile ground = read_profile(ds, corridor, PointFilter::parse("2", "", ""), ThreadPool::shared());
    EXPECT_EQ(keys(ground), brute_force(2));
    EXPECT_LT(ground.points.size(), p.points.size());
}

TEST_F(ProfileRead, CsvAndImage) {
    const Profile p = read_profile(ds, corridor, PointFilter(), ThreadPool::shared());
    write_profile_csv(path("p.csv"), ds, p);
    std::ifstream in(path("p.csv"));
    std::string line;
    std::getline(in, line);
    EXPECT_EQ(line, "distance,x,y,z,class,intensity,return,returns,source_file");
    std::size_t rows = 0;
    while (std::getline(in, line)) {
        if (rows++ == 0) EXPECT_NE(line.find("5205000_3900000.laz\""), std::string::npos) << line;
    }
    EXPECT_EQ(rows, p.points.size());

    ProfileImageScale scale;
    const auto image = profile_image(p, corridor, 800, 300, &scale);
    EXPECT_EQ(image.width, 800);
    EXPECT_EQ(image.height, 300);
    EXPECT_LT(scale.z_min, scale.z_max);
    EXPECT_GT(scale.distance_step, 0);
}

TEST(Corridor, ContainsIsARectangleAlongTheSegment) {
    const Corridor c{0, 0, 10, 0, 2};
    EXPECT_TRUE(c.contains(0, 1));
    EXPECT_TRUE(c.contains(10, -1));
    EXPECT_FALSE(c.contains(10.01, 0));
    EXPECT_FALSE(c.contains(5, 1.01));
    EXPECT_FALSE(c.contains(-0.01, 0));
    EXPECT_DOUBLE_EQ(c.along(3, 0.5), 3);
    EXPECT_THROW(corridor_region({1, 1, 1, 1, 2}), Error);
    const Corridor diagonal{0, 0, 100, 100, 2};
    EXPECT_TRUE(diagonal.touches_box(40, 40, 60, 60));
    EXPECT_TRUE(diagonal.touches_box(50.5, 49, 51, 50));    // the corridor's edge passes within a metre
    EXPECT_FALSE(diagonal.touches_box(80, 0, 100, 20));     // in the segment's box, far from the line
    EXPECT_FALSE(diagonal.touches_box(101, 101, 110, 110)); // beyond the end
    EXPECT_TRUE(diagonal.touches_box(-0.5, -0.5, 0, 0));
}

}  // namespace
}  // namespace lidarscout::pipelines
