// The residency's decisions without threads, on the nine ky-jmo335 tiles: nothing is chosen out of
// view; the tile in view is chosen whole when it fits, in part when only part fits, not at all when
// less than a few pieces would; a held tile out of view is the one dropped for it, while a held tile
// in view worth as much is kept (hysteresis); over the budget the least recently seen goes first; a
// partial tile left by the camera is stale, not for the camera it was loaded for.
#include "viewer/residency_policy.hpp"

#include <gtest/gtest.h>

#include <memory>

#include "dataset/dataset.hpp"
#include "core/patch_grid.hpp"
#include "test_data.hpp"
#include "viewer/point_sets.hpp"
#include "viewer/residency.hpp"

namespace lidarscout::viewer {
namespace {

using Level = ResidencyPolicy::Level;

const dataset::Dataset& survey() {
    static const auto ds = dataset::open_dataset({(test::surveys_dir() / "ky-jmo335-eastern-kentucky").string()});
    return ds;
}

// From 150 m above the middle of a tile, a narrow view that stays inside it.
render::Camera inside(const dataset::Bounds& b) {
    render::Camera c;
    c.x = b.centre_x(), c.y = b.centre_y(), c.z = b.max_z + 150;
    c.pitch_deg = -90;
    c.width = 60, c.height = 90;
    c.near_m = 1, c.far_m = 1e5;
    return c;
}

struct Fixture {
    const dataset::Dataset& ds = survey();
    lidarscout::PatchGrid grid{dataset::patch_grid_origin(survey()).first, dataset::patch_grid_origin(survey()).second};
    ResidencyOptions options;
    std::unique_ptr<ResidencyPolicy> policy;

    Fixture() {
        options.decode_threads = 2;
        policy = std::make_unique<ResidencyPolicy>(ds, grid, options);
    }
    std::uint32_t tile(std::size_t i) const { return static_cast<std::uint32_t>(i); }
    std::uint64_t bytes(std::uint32_t t) const { return tile_point_set_bytes(ds.tiles[t]); }
    // A held entry of `t` at `level` taking `size` bytes, `coarse` of them its coarse levels.
    void hold(std::uint32_t t, Level level, std::uint64_t size, std::uint64_t coarse, std::uint64_t seen = 0) {
        ResidencyPolicy::Entry e;
        e.level = level, e.bytes = size, e.coarse_bytes = coarse, e.last_seen = seen;
        policy->entries()[t] = e;
    }
    ResidencyPolicy::Fractions look(const render::Camera& c, std::uint64_t version = 1) {
        policy->set_camera(c, version);
        return policy->screen_fractions(c);
    }
};

TEST(ResidencyPolicy, ChoosesTheTileInViewWholeOrInPartOrNot) {
    Fixture f;
    const std::uint32_t t = 4;
    const auto fractions = f.look(inside(f.ds.tiles[t].bounds_m));
    ASSERT_EQ(fractions.size(), 1u);
    ASSERT_GT(fractions.of(t), 0.0);
    const std::uint64_t whole = f.bytes(t);

    const auto roomy = f.policy->choose(fractions, 0, 4 * whole);
    ASSERT_TRUE(roomy);
    EXPECT_EQ(roomy->tile, t);
    EXPECT_EQ(roomy->cap, whole) << "whole";
    EXPECT_TRUE(roomy->victims.empty());

    const auto tight = f.policy->choose(fractions, 0, whole / 2);
    ASSERT_TRUE(tight);
    EXPECT_EQ(tight->tile, t);
    EXPECT_LT(tight->cap, whole) << "in part";
    EXPECT_GT(tight->cap, 0u);

    EXPECT_FALSE(f.policy->choose(fractions, 0, 1u << 20)) << "a megabyte: not worth a partial load";
    EXPECT_FALSE(f.policy->choose(f.look(inside(f.ds.tiles[t].bounds_m)), whole, whole))
        << "held bytes leave no room and nothing can be dropped";

    render::Camera away = inside(f.ds.tiles[t].bounds_m);
    away.pitch_deg = 90;  // looking at the sky
    EXPECT_TRUE(f.look(away).empty());
    EXPECT_FALSE(f.policy->choose(f.look(away), 0, 4 * whole));
}

TEST(ResidencyPolicy, DropsWhatIsOutOfViewNotWhatIsWorthAsMuch) {
    Fixture f;
    const std::uint32_t seen = 4, other = 0;
    const std::uint64_t whole = f.bytes(seen);
    // Held out of view: dropped whole (to coarse, then nothing) for the tile in view.
    f.hold(other, Level::Full, whole, whole / 10);
    auto fractions = f.look(inside(f.ds.tiles[seen].bounds_m));
    auto choice = f.policy->choose(fractions, whole, whole + whole / 2);
    ASSERT_TRUE(choice);
    EXPECT_EQ(choice->tile, seen);
    ASSERT_FALSE(choice->victims.empty());
    EXPECT_EQ(choice->victims.front(), other);

    // The tile in view held at full resolution: nothing to choose, and not dropped over budget
    // before the one out of view.
    f.policy->entries().clear();
    f.hold(seen, Level::Full, whole, whole / 10);
    f.hold(other, Level::Coarse, whole / 10, whole / 10);
    fractions = f.look(inside(f.ds.tiles[seen].bounds_m));
    EXPECT_FALSE(f.policy->choose(fractions, whole + whole / 10, 4 * whole));
    EXPECT_EQ(f.policy->wanted(), 1u);
    EXPECT_EQ(f.policy->wanted_full(), 1u);
    const auto over = f.policy->over_budget(whole + whole / 10, whole);
    ASSERT_FALSE(over.empty());
    EXPECT_EQ(over.front(), other) << "out of view goes first";
    EXPECT_TRUE(f.policy->over_budget(whole, 2 * whole).empty()) << "within the budget: nothing";
}

TEST(ResidencyPolicy, LeastRecentlySeenGoesFirst) {
    Fixture f;
    const auto fractions = f.look(inside(f.ds.tiles[4].bounds_m));  // tiles 0, 1, 2 out of view
    (void)fractions;
    const std::uint64_t b = 10u << 20;
    f.hold(0, Level::Coarse, b, b, 7);
    f.hold(1, Level::Coarse, b, b, 3);
    f.hold(2, Level::Coarse, b, b, 5);
    const auto over = f.policy->over_budget(3 * b, b + b / 2);
    ASSERT_EQ(over.size(), 2u);
    EXPECT_EQ(over[0], 1u);
    EXPECT_EQ(over[1], 2u);
}

TEST(ResidencyPolicy, APartialTileLeftByTheCameraIsStale) {
    Fixture f;
    const std::uint32_t t = 4;
    const auto& b = f.ds.tiles[t].bounds_m;
    // Loaded in part for a camera over its south-west quarter: one block there.
    auto block = std::make_shared<LodBlock>();
    block->bounds = {b.min_x, b.min_y, b.min_z, b.min_x + 80, b.min_y + 80, b.max_z};
    block->tile = t;
    ResidencyPolicy::Entry e;
    e.level = Level::Full, e.partial = true, e.loaded_at = 1, e.coverage = 1.0;
    e.blocks = {block};
    f.policy->entries()[t] = e;
    const render::Camera middle = inside(b);
    auto fractions = f.look(middle, 1);
    EXPECT_TRUE(f.policy->stale_partials(fractions).empty()) << "the camera it was loaded for";
    fractions = f.look(middle, 2);
    const auto stale = f.policy->stale_partials(fractions);
    ASSERT_EQ(stale.size(), 1u) << "its block is not in this view";
    EXPECT_EQ(stale[0], t);
}

}  // namespace
}  // namespace lidarscout::viewer
