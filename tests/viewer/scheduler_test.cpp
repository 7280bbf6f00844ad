// The streaming scheduler on real surveys: heightmaps appear before every tile's chunk points
// are in, the memory budget holds while the camera flies over tiles, released tiles leave
// their detail in the heightmaps, a camera move re-prioritises the full-resolution loads, and
// a replica made by the test stays within the budget; heightmaps out of view wait while the
// tiles in view decode and show at the next camera move; files damaged while viewed are listed
// one by one and the rest loads; seen from afar, the heightmaps cover every pixel the points do;
// a tile whose header bounds span billions of metres costs the cells of its data, not of its box.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <map>
#include <mutex>
#include <random>
#include <set>
#include <thread>

#include <unistd.h>

#include "core/process_memory.hpp"
#include "core/thread_pool.hpp"
#include "dataset/chunk_point_loader.hpp"
#include "dataset/dataset.hpp"
#include "synth/replicate.hpp"
#include "test_data.hpp"
#include "render/image_compare.hpp"
#include "viewer/flight_path.hpp"
#include "viewer/frame_refiner.hpp"
#include "viewer/point_sets.hpp"
#include "viewer/reference_frame.hpp"
#include "viewer/scheduler.hpp"
#include "viewer/patch_detail.hpp"
#include "viewer/visibility.hpp"
#include "survey_tiles.hpp"
#include "wait_until.hpp"

namespace lidarscout::viewer {
namespace {

using namespace std::chrono_literals;
using Kind = SchedulerEvent::Kind;

dataset::Dataset open_survey(const std::string& name) {
    return dataset::open_dataset({(test::surveys_dir() / name).string()});
}

using survey::tile_named;

// Straight down at the centre of a tile, `height` metres above its top.
render::Camera above_tile(const dataset::DatasetTile& t, double height) {
    render::Camera c;
    c.x = t.bounds_m.centre_x(), c.y = t.bounds_m.centre_y(), c.z = t.bounds_m.max_z + height;
    c.pitch_deg = -90;
    c.width = 320, c.height = 240;
    c.near_m = 1, c.far_m = 1e5;
    return c;
}

using test::wait_until;

// Events seen by a scheduler's hook, in order.
struct EventLog {
    std::mutex mutex;
    std::vector<SchedulerEvent> events;
    void add(const SchedulerEvent& e) {
        std::lock_guard lock(mutex);
        events.push_back(e);
    }
    std::vector<std::uint32_t> tiles(Kind kind) {
        std::lock_guard lock(mutex);
        std::vector<std::uint32_t> out;
        for (const auto& e : events) {
            if (e.kind == kind) out.push_back(e.tile);
        }
        return out;
    }
};

// Pixels drawn in `covering` among those drawn in `covered` (both drawn on `background`), as a share of the latter.
double share_covered(const render::RgbaImage& covered, const render::RgbaImage& covering, std::uint32_t background) {
    std::size_t drawn = 0, also = 0;
    for (std::size_t i = 0; i < covered.pixels.size(); ++i) {
        if (covered.pixels[i] == background) continue;
        ++drawn;
        also += covering.pixels[i] != background;
    }
    return drawn ? static_cast<double>(also) / static_cast<double>(drawn) : 0.0;
}

TEST(ViewerScheduler, FromAfarTheHeightmapsCoverWhatThePointsCover) {
    // Seen from so far that the survey is a few dozen pixels wide, a heightmap whose outline were
    // drawn by pixel centres alone would leave empty a rim that every point frame fills.
    const auto ds = open_survey("lasr-bcts-strips");
    const auto& b = ds.bounds_m;
    render::Camera camera = above_tile(ds.tiles[0], 0);
    camera.width = 160, camera.height = 120;
    camera.x = 0.5 * (b.min_x + b.max_x), camera.y = 0.5 * (b.min_y + b.max_y);
    camera.z = b.max_z + std::max(b.max_x - b.min_x, b.max_y - b.min_y) * camera.focal_px() / 40.0;
    SchedulerOptions o;
    o.cnn = false, o.full_res = false;
    o.camera = camera;
    Scheduler scheduler(ds, o);
    ASSERT_TRUE(wait_until([&] { return scheduler.idle(); }));
    const auto snapshot = scheduler.snapshot();
    ASSERT_FALSE(snapshot->heightmaps.empty());
    SceneStyle style;
    style.resolve.edl_strength = 0;
    ThreadPool pool(2);
    const SceneLayers heightmaps_only{true, false, false};
    const auto filled = render_snapshot(*snapshot, camera, style, pool, heightmaps_only).image;
    SceneStyle centres = style;
    centres.heightmaps.fill_outline = false;
    const auto by_centres = render_snapshot(*snapshot, camera, centres, pool, heightmaps_only).image;
    const auto points = stream_reference_frame(ds, camera, {}, style, pool);
    const std::uint32_t background = style.resolve.background;
    const double with_fill = share_covered(points, filled, background);
    const double without = share_covered(points, by_centres, background);
    EXPECT_GE(with_fill, 0.97) << "without the fill " << without;
    EXPECT_LT(without, with_fill - 0.05) << "the control: centres alone leave the rim empty";
}

// Without a first camera (the viewer's dataset opening), the chunk points start from the dataset's
// middle: the survey's middle tile is done first, not the tile nearest the CRS origin.
TEST(ViewerScheduler, WithoutACameraChunkPointsStartFromTheMiddle) {
    const auto ds = open_survey("ky-jmo335-eastern-kentucky");
    SchedulerOptions o;
    o.cnn = false, o.full_res = false;
    o.loader.reads.threads = 1;
    EventLog log;
    o.on_event = [&](const SchedulerEvent& e) { log.add(e); };
    Scheduler scheduler(ds, o);
    ASSERT_TRUE(wait_until([&] { return scheduler.idle(); }));
    const auto done = log.tiles(Kind::TileDone);
    ASSERT_EQ(done.size(), 9u);
    EXPECT_EQ(done.front(), tile_named(ds, "N118E380"));
}

// Once every tile's chunk points are in, the grid keeps no spare capacity: it holds what the same points hold
// in a grid filled by a loader and shrunk (and less than before the shrink).
TEST(ViewerScheduler, OnceEveryChunkPointIsInTheGridKeepsNoSpareCapacity) {
    const auto ds = open_survey("ky-jmo335-eastern-kentucky");
    SchedulerOptions o;
    o.cnn = false, o.full_res = false;
    Scheduler scheduler(ds, o);
    ASSERT_TRUE(wait_until([&] { return scheduler.idle(); }));
    const auto [ox, oy] = dataset::patch_grid_origin(ds);
    PatchGrid grid(ox, oy);
    dataset::ChunkPointLoader loader(ds, grid, {});
    loader.start();
    loader.wait();
    ASSERT_EQ(grid.size(), scheduler.grid().size());
    const std::size_t grown = grid.memory_bytes();
    grid.shrink_to_fit();
    EXPECT_LT(grid.memory_bytes(), grown);
    EXPECT_EQ(scheduler.grid().memory_bytes(), grid.memory_bytes());
}

// A scheduler that asks for the network's room waits for the answer before loading it; told there is none, it
// leaves the network out, says so once, and its view ends on linear heightmaps.
TEST(ViewerScheduler, ToldTheNetworkLeavesNoRoomItRunsOnLinearHeightmaps) {
    const auto ds = open_survey("ky-jmo335-eastern-kentucky");
    SchedulerOptions o;
    o.full_res = false;
    o.network_asks_room = true;
    Scheduler scheduler(ds, o);
    EXPECT_GT(scheduler.stats().overview_core_bytes, ds.chunk_point_count * sizeof(GridPoint));
    ASSERT_TRUE(wait_until([&] { return scheduler.stats().linear.done == scheduler.stats().linear.total; }));
    std::this_thread::sleep_for(200ms);
    EXPECT_FALSE(scheduler.idle()) << "the network loaded, or was given up, without an answer";
    scheduler.set_network_room(false);
    ASSERT_TRUE(wait_until([&] { return scheduler.idle(); }));
    const auto st = scheduler.stats();
    EXPECT_TRUE(st.network_declined);
    EXPECT_EQ(st.heightmaps_cnn, 0u);
    EXPECT_GT(st.heightmaps_linear, 0u);
    EXPECT_EQ(std::count_if(st.notes.begin(), st.notes.end(),
                            [](const std::string& n) { return n.find("no room for the heightmap network") !=
                                                              std::string::npos; }),
              1);
}

TEST(ViewerScheduler, HeightmapsStartBeforeAllChunkPointsAreIn) {
    const auto ds = open_survey("ky-jmo335-eastern-kentucky");
    ASSERT_EQ(ds.tiles.size(), 9u);
    SchedulerOptions o;
    o.cnn = false, o.full_res = false;
    o.camera = above_tile(ds.tiles[tile_named(ds, "N119E381")], 2000);  // the south-east corner
    // One reader thread: tiles complete (and call the hook) one at a time, so holding the hook
    // holds all loading; with several, the others finished tiles while one thread waited.
    o.loader.reads.threads = 1;
    Scheduler* sched = nullptr;
    std::atomic<bool> ready{false};
    std::atomic<long> tiles_at_first_heightmap{-1};
    // The loader's thread stops after each tile while heightmap work is pending, so the tiles done
    // when the first heightmap appears are exactly those its window needed.
    o.on_event = [&](const SchedulerEvent& e) {
        if (e.kind != Kind::TileDone || tiles_at_first_heightmap >= 0) return;
        wait_until([&] { return ready.load(); });
        wait_until([&] {
            const auto st = sched->stats();
            return st.heightmaps_linear > 0 || st.heightmap_jobs_pending == 0;
        });
        const auto st = sched->stats();
        if (st.heightmaps_linear > 0) tiles_at_first_heightmap = static_cast<long>(st.tiles_loaded.done);
    };
    Scheduler scheduler(ds, o);
    sched = &scheduler;
    ready = true;
    ASSERT_TRUE(wait_until([&] { return scheduler.idle(); }));
    const auto st = scheduler.stats();
    EXPECT_EQ(st.tiles_loaded.done, 9u);
    EXPECT_GT(st.heightmaps_linear, 0u);
    EXPECT_EQ(st.linear.done, st.linear.total);
    ASSERT_GE(tiles_at_first_heightmap.load(), 1);
    EXPECT_LT(tiles_at_first_heightmap.load(), 9) << "the first heightmap waited for every tile";
    const auto snap = scheduler.snapshot();
    EXPECT_EQ(snap->heightmaps.size(), st.heightmaps_linear);
    EXPECT_TRUE(snap->full_points.empty());
}

// Linear heightmaps only, the camera 150 m above the survey's smallest tile.
SchedulerOptions above_small_tile(const dataset::Dataset& ds) {
    SchedulerOptions o;
    o.cnn = false;
    o.camera = above_tile(ds.tiles[tile_named(ds, "N117E379")], 150);
    return o;
}

// With a content interval, a snapshot for an unmoved camera is kept while chunk points come in; a camera
// move makes a new one at once, and once every tile's chunk points are in the snapshot is the newest.
TEST(ViewerScheduler, WhileChunkPointsComeInTheSnapshotIsKeptForItsCamera) {
    const auto ds = open_survey("ky-jmo335-eastern-kentucky");
    for (const double interval : {3600.0, 0.0}) {
        SchedulerOptions o;
        o.cnn = false, o.full_res = false;
        o.camera = above_tile(ds.tiles[tile_named(ds, "N119E381")], 2000);
        o.loader.reads.threads = 1;  // tiles complete one at a time
        o.content_snapshot_interval_s = interval;
        Scheduler* sched = nullptr;
        std::atomic<bool> ready{false};
        std::shared_ptr<const SceneSnapshot> first, later, moved;
        std::atomic<int> done{0};
        o.on_event = [&](const SchedulerEvent& e) {
            if (e.kind != Kind::TileDone) return;
            wait_until([&] { return ready.load(); });
            const int n = ++done;
            if (n == 2) first = sched->snapshot();
            if (n == 5) {
                // (a tile's chunk points are shown with the next tiles', or by the loader's watch 0.1 s on)
                std::this_thread::sleep_for(std::chrono::milliseconds(300));
                later = sched->snapshot();
                render::Camera c = *o.camera;
                c.z += 100;
                sched->set_camera(c);
                moved = sched->snapshot();
            }
        };
        Scheduler scheduler(ds, o);
        sched = &scheduler;
        ready = true;
        ASSERT_TRUE(wait_until([&] { return scheduler.idle(); }));
        ASSERT_EQ(done.load(), 9);
        ASSERT_TRUE(first && later && moved);
        EXPECT_NE(first->chunk_points.size() + first->heightmaps.size(), 0u);
        if (interval > 0) {
            EXPECT_EQ(later, first) << "three more tiles came in: the snapshot for the same camera was kept";
        } else {
            EXPECT_NE(later, first) << "no interval: every change makes a new snapshot";
        }
        EXPECT_NE(moved, later) << "a camera move makes a new snapshot at once";
        const auto st = scheduler.stats();
        const auto last = scheduler.snapshot();
        EXPECT_EQ(last->heightmaps.size(), st.heightmaps_linear) << "every tile in: the newest content";
        EXPECT_GT(last->heightmaps.size(), 0u);
    }
}

// points_loading() tells a frame whether the points its camera needs are still coming.
TEST(ViewerScheduler, PointsLoadUntilTheTilesInViewAreIn) {
    const auto ds = open_survey("ky-jmo335-eastern-kentucky");
    SchedulerOptions o = above_small_tile(ds);
    Scheduler scheduler(ds, o);
    EXPECT_TRUE(scheduler.points_loading());
    ASSERT_TRUE(wait_until([&] { return !scheduler.points_loading(); }));
    const auto st = scheduler.stats();
    EXPECT_GT(st.full_res.total, 0u);
    EXPECT_EQ(st.full_res.done, st.full_res.total);
    EXPECT_FALSE(scheduler.snapshot()->full_points.empty());
    o.full_res = false;
    const Scheduler without(ds, o);
    EXPECT_FALSE(without.points_loading());
}

TEST(ViewerScheduler, MemoryBudgetHoldsAndReleasedTilesLeaveTheirDetail) {
    const auto ds = open_survey("ky-jmo335-eastern-kentucky");
    const std::vector<std::uint32_t> path = {tile_named(ds, "N117E379"), tile_named(ds, "N119E379"),
                                             tile_named(ds, "N117E381"), tile_named(ds, "N119E381")};
    std::uint64_t largest = 0;
    for (const auto t : path) largest = std::max(largest, tile_point_set_bytes(ds.tiles[t]));
    SchedulerOptions o;
    o.cnn = false;
    o.memory_budget = 28ull << 20;  // about two of these tiles besides the heightmaps
    o.camera = above_tile(ds.tiles[path[0]], 150);
    EventLog log;
    std::atomic<Scheduler*> sched{nullptr};
    std::atomic<std::uint64_t> worst_full_res{0};
    o.on_event = [&](const SchedulerEvent& e) {
        log.add(e);
        if (e.kind == Kind::FullResLoaded && sched) {
            worst_full_res = std::max(worst_full_res.load(), sched.load()->stats().bytes_full_res);
        }
    };
    Scheduler scheduler(ds, o);
    sched = &scheduler;
    for (const auto t : path) {
        scheduler.set_camera(above_tile(ds.tiles[t], 150));
        ASSERT_TRUE(wait_until([&] { return scheduler.idle(); })) << ds.tiles[t].tile.path();
        const auto loaded = log.tiles(Kind::FullResLoaded);
        EXPECT_NE(std::find(loaded.begin(), loaded.end(), t), loaded.end()) << ds.tiles[t].tile.path();
        const auto st = scheduler.stats();
        EXPECT_LE(st.bytes_used, o.memory_budget);
        // A tile decoding beside what is held: its points, and the piece each of the two decoding
        // threads has on the way (records and points).
        EXPECT_LE(st.peak_bytes_used, o.memory_budget + 2 * largest);
    }
    EXPECT_LE(worst_full_res.load(), o.memory_budget);
    const auto released = log.tiles(Kind::FullResReleased);
    ASSERT_FALSE(released.empty()) << "four tiles cannot all stay within the budget";

    // The released tile's points, decoded here: the busiest texel well inside the tile holds
    // their mean height in the patch's heightmap.
    const auto& tile = ds.tiles[released.front()];
    ThreadPool pool(2);
    const PointSet set = tile_point_set(tile, ds.las_stride, pool);
    const PatchDetails detail = tile_detail(set, scheduler.grid(), 64);
    const lidarscout::CellKey* best_cell = nullptr;
    std::size_t best_texel = 0;
    std::uint32_t best_count = 0;
    for (const auto& [cell, d] : detail) {
        for (int row = 0; row < d.size; ++row) {
            for (int col = 0; col < d.size; ++col) {
                const double x = d.origin_x + (col + 0.5) * d.texel_m, y = d.origin_y + (row + 0.5) * d.texel_m;
                const auto& b = tile.bounds_m;
                if (x < b.min_x + 20 || x > b.max_x - 20 || y < b.min_y + 20 || y > b.max_y - 20) continue;
                const std::size_t t = static_cast<std::size_t>(row) * d.size + col;
                if (d.all.count[t] > best_count && scheduler.heightmap(cell)) {
                    best_cell = &cell, best_texel = t, best_count = d.all.count[t];
                }
            }
        }
    }
    ASSERT_NE(best_cell, nullptr);
    double sum = 0;
    std::uint32_t n = 0;
    const auto& d = detail.at(*best_cell);
    for (const auto& p : set.points) {
        const double x = set.origin_x + p.dx, y = set.origin_y + p.dy;
        const int col = static_cast<int>((x - d.origin_x) / d.texel_m),
                  row = static_cast<int>((y - d.origin_y) / d.texel_m);
        if (scheduler.grid().cell_of(x, y) == *best_cell &&
            static_cast<std::size_t>(row * d.size + col) == best_texel) {
            sum += set.origin_z + p.dz;
            ++n;
        }
    }
    ASSERT_EQ(n, best_count);
    const auto h = scheduler.heightmap(*best_cell);
    ASSERT_TRUE(h);
    EXPECT_NEAR(h->heights[best_texel], sum / n, 0.01);
}

TEST(ViewerScheduler, MovingTheCameraReprioritisesFullResolution) {
    const auto ds = open_survey("ky-jmo335-eastern-kentucky");
    const std::uint32_t a = tile_named(ds, "N117E379"), b = tile_named(ds, "N119E381");
    SchedulerOptions o;
    o.cnn = false;
    o.camera = above_tile(ds.tiles[a], 150);
    EventLog log;
    o.on_event = [&](const SchedulerEvent& e) { log.add(e); };
    Scheduler scheduler(ds, o);
    ASSERT_TRUE(wait_until([&] { return !log.tiles(Kind::FullResLoaded).empty(); }));
    EXPECT_EQ(log.tiles(Kind::FullResLoaded).front(), a);
    ASSERT_TRUE(wait_until([&] { return scheduler.idle(); }));  // A's neighbours in view are in too
    const std::size_t before = log.tiles(Kind::FullResLoaded).size();
    scheduler.set_camera(above_tile(ds.tiles[b], 150));
    ASSERT_TRUE(wait_until([&] { return log.tiles(Kind::FullResLoaded).size() > before; }));
    EXPECT_EQ(log.tiles(Kind::FullResLoaded)[before], b);
    std::set<std::uint32_t> tiles;
    for (const auto& b : scheduler.snapshot()->full_points) tiles.insert(b->tile);
    EXPECT_GE(tiles.size(), 2u);
}

// Out-of-view patches get their heightmaps only once every visible tile is decoded (the
// residency idle), and then they do get them.
TEST(ViewerScheduler, HeightmapsOutOfViewWaitForTheTilesInView) {
    const auto ds = open_survey("ky-jmo335-eastern-kentucky");
    const std::uint32_t a = tile_named(ds, "N117E379");
    SchedulerOptions o;
    o.cnn = false;
    o.camera = above_tile(ds.tiles[a], 150);
    std::atomic<Scheduler*> sched{nullptr};
    std::atomic<int> out_of_view{0}, early{0};
    o.on_event = [&](const SchedulerEvent& e) {
        Scheduler* s = sched.load();
        if (e.kind != Kind::LinearHeightmap || !s) return;
        const auto box = cell_box(s->grid(), e.cell, ds.bounds_m.min_z, ds.bounds_m.max_z);
        if (box_in_view(*o.camera, box)) return;
        ++out_of_view;
        const auto st = s->stats();
        if (st.full_res.total == 0 || st.full_res.done < st.full_res.total) ++early;
    };
    Scheduler scheduler(ds, o);
    sched = &scheduler;
    ASSERT_TRUE(wait_until([&] { return scheduler.idle(); }));
    EXPECT_EQ(early.load(), 0) << "a heightmap out of view was built while the tiles in view decoded";
    EXPECT_GT(out_of_view.load(), 0) << "the patches out of view never got their heightmaps";
    sched = nullptr;
}

// Heightmaps built out of view do not change the snapshot of a still camera (its picture is
// done, and its refined frame must come), and show at the next camera move.
TEST(ViewerScheduler, HeightmapsOutOfViewShowAtTheNextCameraMove) {
    const auto ds = open_survey("ky-jmo335-eastern-kentucky");
    SchedulerOptions o = above_small_tile(ds);
    Scheduler scheduler(ds, o);
    ASSERT_TRUE(wait_until([&] {
        scheduler.snapshot();  // taken every frame, as the viewer does
        return scheduler.idle();
    }));
    const auto still = scheduler.snapshot();
    const std::size_t all = scheduler.stats().heightmaps_linear;
    EXPECT_LT(still->heightmaps.size(), all) << "every heightmap out of view was in the still camera's snapshot";
    render::Camera moved = *o.camera;
    moved.yaw_deg += 1;
    scheduler.set_camera(moved);
    const auto after = scheduler.snapshot();
    EXPECT_NE(after->version, still->version);
    EXPECT_EQ(after->heightmaps.size(), all);
}

// Once idle with a budget that holds the survey, the still frame (refined: every point held)
// equals a frame drawing every point of the tile decoded here, over the same heightmaps; the
// frame drawn while moving (LOD at half a pixel) is close to it but not equal.
// Linear heightmaps and full resolution within 1 GiB, starting at `camera`.
SchedulerOptions linear_full_res(const render::Camera& camera) {
    SchedulerOptions o;
    o.cnn = false;
    o.memory_budget = 1ull << 30;
    o.camera = camera;
    return o;
}

TEST(ViewerScheduler, IdleFrameEqualsEveryPointOfTheVisibleTiles) {
    const auto ds = open_survey("ky-woodford-county");
    ASSERT_EQ(ds.tiles.size(), 1u);
    render::Camera camera = above_tile(ds.tiles[0], 1500);
    camera.width = 480, camera.height = 360;
    Scheduler scheduler(ds, linear_full_res(camera));
    ASSERT_TRUE(wait_until([&] { return scheduler.idle(); }));
    EXPECT_EQ(scheduler.stats().full_res.done, 1u);
    const auto snap = scheduler.snapshot();
    ThreadPool pool(2);
    SceneStyle style;
    FrameRefiner refiner(std::chrono::milliseconds(0));
    const auto moving = refiner.draw(*snap, camera, style, pool).image;
    const auto still = refiner.draw(*snap, camera, style, pool).image;
    ASSERT_TRUE(refiner.refined());

    Scene reference;
    for (const auto& h : snap->heightmaps) reference.heightmaps.push_back(*h);
    for (const auto& c : snap->chunk_points) reference.chunk_points.push_back(*c);
    reference.full_points.push_back(tile_point_set(ds.tiles[0], ds.las_stride, pool));
    if (!scheduler.has_rgb()) paint_uncoloured(reference.full_points);
    const auto expected = render_scene(reference, camera, style, pool).image;
    EXPECT_GE(render::image_psnr_db(still, expected), 60.0);
    const double lod = render::image_psnr_db(moving, expected);
    RecordProperty("lod_psnr_db", static_cast<int>(lod));
    EXPECT_GE(lod, 30.0);
    EXPECT_LT(lod, render::kIdenticalPsnrDb);
}

TEST(ViewerScheduler, AGroundSurfaceLaysTheDetailOverAgainAsBareEarth) {
    // ky-woodford-county read whole, then a ground filter: every patch with detail shows bare earth
    // (its ground texels at the mean of their ground points), laid over in the background; the
    // frame meanwhile tints what still shows every point. Back to every point, the detail returns.
    const auto ds = open_survey("ky-woodford-county");
    Scheduler scheduler(ds, linear_full_res(above_tile(ds.tiles[0], 1500)));
    ASSERT_TRUE(wait_until([&] { return scheduler.idle(); }));
    ThreadPool pool(2);
    const PatchDetails details = tile_detail(tile_point_set(ds.tiles[0], ds.las_stride, pool), scheduler.grid(), 64);
    const auto shown_surfaces = [&](Surface wanted) {
        std::size_t n = 0, checked = 0;
        for (const auto& [cell, d] : details) {
            const auto h = scheduler.heightmap(cell);
            if (!h) continue;
            ++n;
            EXPECT_EQ(h->surface, wanted);
            const DetailLayer& layer = wanted == Surface::Ground ? d.ground : d.all;
            for (std::size_t t = 0; t < h->heights.size() && !layer.empty(); ++t) {
                if (layer.count[t] == 0) continue;
                EXPECT_NEAR(h->heights[t], layer.height[t], 1e-3) << "texel " << t;
                ++checked;
            }
        }
        return std::pair{n, checked};
    };
    const auto [patches, all_texels] = shown_surfaces(Surface::All);
    ASSERT_GT(patches, 0u);
    ASSERT_GT(all_texels, 0u);
    scheduler.set_surface(Surface::Ground);
    EXPECT_EQ(scheduler.surface(), Surface::Ground);
    EXPECT_FALSE(scheduler.idle() && scheduler.stats().surface_pending > 0);
    ASSERT_TRUE(wait_until([&] { return scheduler.idle(); }));
    EXPECT_EQ(scheduler.stats().surface_pending, 0u);
    const auto [ground_patches, ground_texels] = shown_surfaces(Surface::Ground);
    EXPECT_EQ(ground_patches, patches);
    EXPECT_GT(ground_texels, all_texels / 4) << "a classified survey: ground in much of it";
    EXPECT_LT(ground_texels, all_texels) << "and roofs or trees where there is none";
    scheduler.set_surface(Surface::All);
    ASSERT_TRUE(wait_until([&] { return scheduler.idle(); }));
    EXPECT_EQ(shown_surfaces(Surface::All).second, all_texels);
}

// A replica made by the test itself: the 9 ky-jmo335 tiles on a 6x6 grid (36 tiles, 63 M
// points, ~1.3 GB as full-resolution points), in a temporary folder removed at the end.
class Replica {
public:
    explicit Replica(synth::GridSize grid) {
        dir_ = std::filesystem::temp_directory_path() / ("lidarscout_replica_" + std::to_string(::getpid()));
        const auto plan = synth::plan_replicas({(test::surveys_dir() / "ky-jmo335-eastern-kentucky").string()},
                                               dir_.string(), grid);
        ThreadPool pool(2);
        synth::write_replicas(plan, pool);
    }
    ~Replica() { std::filesystem::remove_all(dir_); }
    std::string path() const { return dir_.string(); }

private:
    std::filesystem::path dir_;
};

TEST(ViewerScheduler, ReplicatedDatasetStaysWithinTheMemoryBudget) {
    const Replica replica({6, 6});
    const auto ds = dataset::open_dataset({replica.path()});
    ASSERT_EQ(ds.tiles.size(), 36u);
    SchedulerOptions o;
    o.cnn = false;
    o.memory_budget = 192ull << 20;  // a seventh of the replica's points
    // The limit (the budget plus 15%), and what the scheduler's threads hold outside it
    // (their stacks, the chunk point reader's buffers).
    const std::uint64_t margin = o.memory_budget * 15 / 100 + (32ull << 20);
    const std::uint64_t rss0 = resident_bytes();
    // Down from high above the whole dataset to low over a diagonal, in 20 steps; each step waits until the
    // scheduler has done what its view asks (or 15 s), so that a loaded machine flies as far into the budget
    // as an idle one (a flight timed by the clock saw no release when the suite ran beside other builds).
    FlightPath path;
    path.width = 640, path.height = 360;
    const auto camera_at = [&](double t) { return flight_camera(ds.bounds_m, t, path); };
    o.camera = camera_at(0);
    Scheduler scheduler(ds, o);
    std::uint64_t worst = 0;
    for (int step = 0; step <= 20; ++step) {
        scheduler.set_camera(camera_at(step / 20.0));
        const auto deadline = std::chrono::steady_clock::now() + 15s;
        do {
            (void)scheduler.snapshot();
            worst = std::max(worst, resident_bytes());
            std::this_thread::sleep_for(100ms);
        } while (!scheduler.idle() && std::chrono::steady_clock::now() < deadline);
    }
    const auto st = scheduler.stats();
    RecordProperty("peak_rss_mb", static_cast<int>(worst >> 20));
    std::printf("replica: peak RSS %llu MB (%llu MB before), scheduler peak %llu MB of %llu MB; %zu heightmaps, "
                "%zu full-res tiles, %zu released\n",
                (unsigned long long)(worst >> 20), (unsigned long long)(rss0 >> 20),
                (unsigned long long)(st.peak_bytes_used >> 20), (unsigned long long)(st.memory_budget >> 20),
                st.heightmaps_linear, st.full_res_tiles, st.full_res_released);
    // What the process held before the scheduler (the dataset's headers here; in a run of the
    // whole suite in one process, everything earlier tests left) is not the scheduler's.
    EXPECT_LE(worst - std::min(worst, rss0), o.memory_budget + margin);
    EXPECT_GT(st.heightmaps_linear, 0u);
    EXPECT_GT(st.full_res_released, 0u) << "the flight never filled the budget: the test checks nothing";
}

// Issue 14.5: files damaged while they are viewed. Eight real tiles copied into a temporary
// folder and opened; then one is truncated and one deleted before the scheduler reads their
// points, and while it streams (a scripted flight) a helper thread overwrites a third with
// random bytes of the same size. Each tile that fails is listed with its path and cause, the
// others reach full resolution, nothing of a failed tile is held, and nothing crashes.
TEST(ViewerScheduler, FilesDamagedDuringASessionAreListedAndTheRestLoads) {
    namespace fs = std::filesystem;
    const fs::path dir = fs::temp_directory_path() / ("lidarscout_faults_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    for (const auto& e : fs::directory_iterator(test::surveys_dir() / "ky-jmo335-eastern-kentucky")) {
        if (e.path().extension() == ".laz" && e.path().stem() != "N118E380") {
            fs::copy_file(e.path(), dir / e.path().filename());
        }
    }
    const auto ds = dataset::open_dataset({dir.string()});
    ASSERT_EQ(ds.tiles.size(), 8u);
    const fs::path truncated = dir / "N117E380.laz", deleted = dir / "N119E380.laz", scribbled = dir / "N118E381.laz";
    fs::resize_file(truncated, fs::file_size(truncated) / 3);
    fs::remove(deleted);
    std::thread vandal([&] {
        std::this_thread::sleep_for(300ms);
        std::vector<char> noise(fs::file_size(scribbled));
        std::mt19937 rng(5);
        for (auto& c : noise) c = static_cast<char>(rng());
        std::FILE* f = std::fopen(scribbled.c_str(), "r+b");
        if (f) std::fwrite(noise.data(), 1, noise.size(), f), std::fclose(f);
    });
    SchedulerOptions o;
    o.cnn = false;
    o.memory_budget = 1ull << 30;
    FlightPath path;
    path.width = 320, path.height = 180;
    const auto camera_at = [&](double t) { return flight_camera(ds.bounds_m, t, path); };
    o.camera = camera_at(0);
    {
        Scheduler scheduler(ds, o);
        const auto start = std::chrono::steady_clock::now();
        for (double t = 0; t < 1.0;) {  // the flight, 4 s
            scheduler.set_camera(camera_at(t));
            (void)scheduler.snapshot();
            std::this_thread::sleep_for(20ms);
            t = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() / 4.0;
        }
        vandal.join();
        render::Camera whole = camera_at(0);  // back above everything until all is done
        scheduler.set_camera(whole);
        ASSERT_TRUE(wait_until([&] { return scheduler.idle(); }));
        const auto st = scheduler.stats();
        std::map<std::string, std::string> causes;  // file name -> first cause
        for (const auto& e : st.errors) causes.emplace(fs::path(e.file).filename().string(), e.cause);
        for (const auto& e : first_error_per_file(st.errors)) std::printf("error: %s\n", e.first.message().c_str());
        ASSERT_TRUE(causes.contains("N117E380.laz")) << "the truncated tile is not listed";
        ASSERT_TRUE(causes.contains("N119E380.laz")) << "the deleted tile is not listed";
        EXPECT_FALSE(causes["N117E380.laz"].empty());
        EXPECT_NE(causes["N119E380.laz"].find("No such file"), std::string::npos) << causes["N119E380.laz"];
        for (const auto& [name, cause] : causes) {
            EXPECT_TRUE(name == "N117E380.laz" || name == "N119E380.laz" || name == "N118E381.laz")
                << name << ": " << cause;
        }
        // The undamaged tiles are all at full resolution; nothing of a failed tile is drawn.
        EXPECT_EQ(st.full_res.done, st.full_res.total) << "visible tiles not at full resolution";
        EXPECT_GE(st.full_res.total, 4u) << "the last camera sees too little: the test checks nothing";
        EXPECT_EQ(st.full_res_tiles, st.full_res.done);
        std::set<std::uint32_t> failed;
        for (std::uint32_t i = 0; i < ds.tiles.size(); ++i) {
            if (causes.contains(fs::path(ds.tiles[i].tile.path()).filename().string())) failed.insert(i);
        }
        for (const auto& b : scheduler.snapshot()->full_points) {
            EXPECT_FALSE(failed.contains(b->tile))
                << "blocks of a failed tile are held: " << ds.tiles[b->tile].tile.path();
        }
        EXPECT_EQ(first_error_per_file(st.errors).size(), causes.size());
        EXPECT_LE(st.peak_bytes_used, o.memory_budget);
    }
    fs::remove_all(dir);
}

// 1,024 points in bounds of +-2.1e9 m: the scheduler enumerated 4.3e13 cells of its box and
// hung past 3 GB. Now the patches are the cells its 4 chunk points fell in.
TEST(ViewerScheduler, TileWithHugeBoundsCostsItsDataNotItsBox) {
    const auto path = test::formats_dir() / "visgl__loaders.gl/modules__las__test__data__pdrf6-1.4.laz";
    const dataset::Dataset ds = dataset::open_dataset({path.string()});
    ASSERT_EQ(ds.tiles.size(), 1u);
    ASSERT_GT(ds.bounds_m.max_x - ds.bounds_m.min_x, 4e9);
    const std::uint64_t before = resident_bytes();
    SchedulerOptions o;
    o.cnn = false;
    o.memory_budget = 256ull << 20;
    const auto& b = ds.bounds_m;
    o.camera = render::Camera::looking_at_bounds(b.min_x, b.min_y, b.min_z, b.max_x, b.max_y, b.max_z, 320, 240, 60);
    Scheduler scheduler(ds, o);
    ASSERT_TRUE(wait_until([&] { return scheduler.idle(); }));
    const SchedulerStats st = scheduler.stats();
    EXPECT_EQ(st.chunk_points_loaded, 4u);
    EXPECT_GE(st.linear.total, 1u);
    EXPECT_LE(st.linear.total, 4u);  // the cells its chunk points fell in
    EXPECT_EQ(st.linear.done, st.linear.total);
    const auto snapshot = scheduler.snapshot();
    std::size_t drawn = 0;
    for (const auto& set : snapshot->chunk_points) drawn += set->points.size();
    EXPECT_LE(drawn, 4u);
    EXPECT_GE(drawn + snapshot->heightmaps.size(), 1u);  // its points, or a heightmap over them
    EXPECT_LT(resident_bytes(), before + (256ull << 20));
}

}  // namespace
}  // namespace lidarscout::viewer
