// raster::dem_request and raster::dem_plan (the CLI's `dem` options and `--plan N`, and the Python
// module's dem, dem_plan and dem_block): the options a command line checks as it reads them are checked
// again, with the CLI's words; combinations dem refuses are refused; the defaults are dem's; the plan's
// pieces cover the grid's blocks once, numbered from 1, with the points of the tiles between them.
#include <gtest/gtest.h>

#include <set>
#include <string>

#include "dataset/dataset.hpp"
#include "raster/dem_options.hpp"
#include "test_data.hpp"

namespace lidarscout {
namespace {

std::string refusal(const raster::DemOptions& o) {
    try {
        raster::dem_request(o);
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

TEST(DemOptions, NumbersAndCombinationsAreRefusedAsTheCliSaysIt) {
    raster::DemOptions o;
    o.method = "idw";
    o.radius = 0;
    EXPECT_EQ(refusal(o), "dem: --radius: must be more than 0, not '0'");
    o.radius.reset();
    o.texel = -1;
    EXPECT_EQ(refusal(o), "dem: --texel: must be more than 0, not '-1'");
    o = {};
    o.max_edge = -2.5;
    EXPECT_EQ(refusal(o), "dem: --max-edge: must be 0 or more, not '-2.5'");
    o = {};
    o.product = "dtm";
    o.method = "mean";
    EXPECT_EQ(refusal(o), "dem: --method does not apply to --product");
    o = {};
    o.ground_options = {"--ground-cell"};
    EXPECT_EQ(refusal(o), "dem: --ground applies to --product dtm or chm");
    o = {};
    o.bounds = {1, 2, 3};
    EXPECT_NE(refusal(o).find("--bounds expects four numbers"), std::string::npos);
    o = {};
    o.block = "5/4";
    EXPECT_NE(refusal(o).find("--block"), std::string::npos);
}

TEST(DemOptions, DefaultsAreDems) {
    raster::DemOptions o;
    o.memory = 1 << 30;
    o.threads = 3;
    raster::DemRequest r = raster::dem_request(o);
    EXPECT_EQ(r.method, raster::DemMethod::Mean);
    EXPECT_EQ(r.source, raster::DemSource::Full);
    EXPECT_TRUE(r.products.empty());
    EXPECT_EQ(r.memory_budget, 1u << 30);
    EXPECT_EQ(r.threads, 3u);
    EXPECT_EQ(r.block_count, 0);
    o.from = "overview";
    o.block = "2/3";
    r = raster::dem_request(o);
    EXPECT_EQ(r.method, raster::DemMethod::Linear);
    EXPECT_EQ(r.block_index, 2);
    EXPECT_EQ(r.block_count, 3);
    o = {};
    o.product = "dtm,chm";
    o.classes = "2";
    r = raster::dem_request(o);
    ASSERT_EQ(r.products.size(), 2u);
    EXPECT_TRUE(r.product_options.classes_given);
}

TEST(DemOptions, ThePlanCoversTheGridOnce) {
    const dataset::Dataset ds = dataset::open_dataset({(test::surveys_dir() / "ky-woodford-county").string()});
    raster::DemOptions o;
    o.product = "dtm";
    const raster::DemPlan plan = raster::dem_plan(ds, raster::dem_request(o), 4);
    ASSERT_EQ(plan.pieces.size(), 4u);
    EXPECT_EQ(plan.points, ds.point_count);
    std::set<std::pair<int, int>> blocks;
    double points = 0;
    for (std::size_t i = 0; i < plan.pieces.size(); ++i) {
        const raster::DemPiece& p = plan.pieces[i];
        EXPECT_EQ(p.index, static_cast<int>(i + 1));
        EXPECT_GT(p.memory_estimate, 0u);
        points += p.points;
        for (int y = p.blocks.y0; y <= p.blocks.y1; ++y) {
            for (int x = p.blocks.x0; x <= p.blocks.x1; ++x) EXPECT_TRUE(blocks.insert({x, y}).second);
        }
    }
    EXPECT_EQ(static_cast<std::int64_t>(blocks.size()), plan.blocks);
    EXPECT_NEAR(points, static_cast<double>(plan.points), 1.0);
    EXPECT_THROW(raster::dem_plan(ds, raster::dem_request(o), static_cast<int>(plan.blocks) + 1), Error);
}

}  // namespace
}  // namespace lidarscout
