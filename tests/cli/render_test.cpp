// `lidarscout render`: every survey rendered at the auto camera shows terrain in elevation
// colours; the overview draws less than the heightmaps; full resolution decodes a small
// survey's tile; golden images at a fixed camera; bad arguments are one-line errors, and so is a
// remote tile whose every chunk point failed; a corrupt chunk costs only its points (exit 3).
//
// Golden images live in tests/data/golden/. After an intended change of the rendering, look
// at the new images and regenerate them with
//   LIDARSCOUT_UPDATE_GOLDEN=1 build/lidarscout_tests --gtest_filter='RenderCommand.Golden*'
// (the test then writes the rendered PNGs over the references and passes).
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <fstream>
#include <iterator>
#include <string>
#include <thread>

#include "core/thread_pool.hpp"
#include "dataset/dataset.hpp"
#include "core/point_filter.hpp"
#include "dataset/point_reader.hpp"
#include "io/file.hpp"
#include "las/point_format.hpp"
#include "nn/heightmap_network.hpp"
#include "render/framebuffer.hpp"
#include "net/fault_server.hpp"
#include "render/image_compare.hpp"
#include "viewer/frame_refiner.hpp"
#include "viewer/scheduler.hpp"
#include "nginx_server.hpp"
#include "damaged_tile.hpp"
#include "png_test_util.hpp"
#include "test_data.hpp"


namespace lidarscout {
namespace {

namespace fs = std::filesystem;

using test::drawn_pixels;
using test::kBackground;
using test::Png;
using test::read_png;

// Hue sectors (of 30 degrees) of the drawn, not greyish pixels holding at least `min_share` of
// them: shading scales a colour and keeps its hue, so several sectors mean several elevations.
int hue_sectors(const Png& png, double min_share) {
    std::map<int, std::size_t> sectors;
    std::size_t drawn = 0;
    for (const std::uint32_t p : png.pixels) {
        if ((p & 0xffffff) == (kBackground & 0xffffff)) continue;
        ++drawn;
        const double r = render::red(p), g = render::green(p), b = render::blue(p);
        const double hi = std::max({r, g, b}), lo = std::min({r, g, b}), c = hi - lo;
        if (c < 12) continue;
        double h = hi == r ? std::fmod((g - b) / c + 6.0, 6.0) : hi == g ? (b - r) / c + 2.0 : (r - g) / c + 4.0;
        ++sectors[static_cast<int>(h * 60.0 / 30.0) % 12];
    }
    return static_cast<int>(std::count_if(sectors.begin(), sectors.end(),
                                          [&](const auto& s) { return s.second >= std::max(1.0, min_share * drawn); }));
}

class RenderCommand : public ::testing::Test {
protected:
    fs::path dir_ = fs::temp_directory_path() / ("lidarscout_render_test_" + std::to_string(::getpid()));
    void SetUp() override { fs::create_directories(dir_); }
    void TearDown() override { fs::remove_all(dir_); }

    // Runs `lidarscout render ARGS -o DIR/NAME.png`; stdout into `out`, stderr into `err`.
    int render(const std::string& args, const std::string& name, std::string& out, std::string& err) {
        const fs::path err_file = dir_ / (name + ".err");
        const int rc = test::run_command(std::string(LIDARSCOUT_CLI) + " render " + args + " -o " +
                                             (dir_ / (name + ".png")).string() + " 2>" + err_file.string(),
                                         out);
        std::ifstream in(err_file);
        err.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
        return rc;
    }
    nlohmann::json render_json(const std::string& args, const std::string& name) {
        std::string out, err;
        EXPECT_EQ(render(args + " --json", name, out, err), 0) << err;
        return nlohmann::json::parse(out, nullptr, false);
    }
    Png png(const std::string& name) const { return read_png(dir_ / (name + ".png")); }
};

std::string survey(const std::string& name) { return (test::surveys_dir() / name).string(); }

// Share of the 320 x 240 image the heightmaps stage covers at the auto camera and hue sectors
// of its elevation colours, with margin (measured: ky-jmo335 0.50 / 7, ky-woodford 0.46 / 3,
// ky-red-river 0.38 / 7, nc-raleigh 0.14 / 5, lasr-bcts 0.089 / 6, isprs 0.0053 / 2, ign
// 0.0004 / 6). The IGN tiles lie hundreds of km apart (France from the air, 29 chunk points,
// no patch with enough of them), the ISPRS sites kilometres apart.
struct Expect {
    double min_share;
    int min_hues;
};
const std::map<std::string, Expect> kExpected = {
    {"ky-jmo335-eastern-kentucky", {0.35, 4}}, {"ky-woodford-county", {0.30, 2}}, {"ky-red-river-gorge", {0.25, 4}},
    {"nc-raleigh-ept", {0.08, 3}},           {"lasr-bcts-strips", {0.05, 4}},   {"isprs-filter-test-sites", {0.003, 2}},
    {"ign-lidar-hd-1km", {0.0002, 3}},
};

TEST_F(RenderCommand, EverySurveyShowsTerrainInElevationColours) {
    int surveys = 0;
    for (const auto& entry : fs::directory_iterator(test::surveys_dir())) {
        if (!entry.is_directory()) continue;
        const std::string name = entry.path().filename().string();
        SCOPED_TRACE(name);
        ++surveys;
        std::string out, err;
        ASSERT_EQ(render(entry.path().string() + " --camera auto --until heightmaps --size 320x240 --colour elevation",
                         name, out, err),
                  0)
            << err;
        EXPECT_NE(err.find("render: "), std::string::npos) << err;  // the one-line summary
        const Png image = png(name);
        ASSERT_TRUE(image.ok());
        EXPECT_EQ(image.width, 320);
        EXPECT_EQ(image.height, 240);
        const auto it = kExpected.find(name);
        const Expect e = it != kExpected.end() ? it->second : Expect{0.0001, 1};
        const double share = static_cast<double>(drawn_pixels(image)) / (320 * 240);
        EXPECT_GE(share, e.min_share);
        EXPECT_GE(hue_sectors(image, 0.02), e.min_hues);
    }
    EXPECT_EQ(surveys, 7);
}

TEST_F(RenderCommand, OverviewDrawsLessThanHeightmaps) {
    const std::string args = survey("ky-jmo335-eastern-kentucky") + " --size 320x240 --colour elevation";
    const auto overview = render_json(args + " --until overview", "overview");
    const auto heightmaps = render_json(args + " --until heightmaps", "heightmaps");
    EXPECT_EQ(overview.at("patches_with_heightmaps"), 0);
    EXPECT_EQ(overview.at("chunk_points_drawn"), overview.at("chunk_points"));
    EXPECT_GT(heightmaps.at("patches_with_heightmaps").get<int>(), 10);
    EXPECT_EQ(heightmaps.at("full_res_points"), 0);
    const std::size_t drawn_overview = drawn_pixels(png("overview")),
                      drawn_heightmaps = drawn_pixels(png("heightmaps"));
    EXPECT_EQ(drawn_overview, overview.at("drawn_pixels").get<std::size_t>());
    EXPECT_EQ(drawn_heightmaps, heightmaps.at("drawn_pixels").get<std::size_t>());
    EXPECT_GT(drawn_overview, 100u);
    EXPECT_GT(drawn_heightmaps, 10 * drawn_overview);
}

TEST_F(RenderCommand, FullDecodesTheTileOfASmallSurvey) {
    const std::string args = survey("ky-woodford-county") + " --size 320x240";
    const auto heightmaps = render_json(args + " --until heightmaps", "heightmaps");
    const auto full = render_json(args + " --until full --point-size 2", "full");
    EXPECT_EQ(full.at("tiles"), 1);
    EXPECT_EQ(full.at("full_res_tiles"), 1);
    EXPECT_EQ(full.at("full_res_points"), 1'012'412);  // the tile's point count
    EXPECT_TRUE(full.at("has_rgb").get<bool>());
    EXPECT_GE(full.at("drawn_pixels").get<std::size_t>(), heightmaps.at("drawn_pixels").get<std::size_t>());
    for (const char* key : {"headers", "chunk_points", "heightmaps", "full_res", "render"}) {
        EXPECT_GE(full.at("seconds").at(key).get<double>(), 0.0) << key;
    }
    // The full-resolution points change most of what is drawn.
    const Png a = png("heightmaps"), b = png("full");
    ASSERT_TRUE(a.ok() && b.ok());
    std::size_t changed = 0;
    for (std::size_t i = 0; i < a.pixels.size(); ++i) changed += a.pixels[i] != b.pixels[i];
    EXPECT_GT(changed, drawn_pixels(a) / 2);

    const auto budget = render_json(args + " --until full --memory 1M", "budget");  // 20 MB of points do not fit
    EXPECT_EQ(budget.at("full_res_tiles"), 0);
    EXPECT_EQ(budget.at("full_res_tiles_over_budget"), 1);
    EXPECT_EQ(budget.at("full_res_points"), 0);
}

// The camera `render --json` reports (its position in metres), for `width` x `height` pixels.
render::Camera reported_camera(const nlohmann::json& j) {
    const auto& c = j.at("camera");
    render::Camera camera;
    const auto& m = c.at("position_m");
    camera.x = m.at(0), camera.y = m.at(1), camera.z = m.at(2);
    camera.yaw_deg = c.at("yaw_deg"), camera.pitch_deg = c.at("pitch_deg"), camera.fov_deg = c.at("fov_deg");
    camera.near_m = c.at("near_m"), camera.far_m = c.at("far_m");
    camera.width = j.at("width"), camera.height = j.at("height");
    return camera;
}

// The viewer's settled frame of `paths` at `camera` once its scheduler is idle (every tile in view in).
render::RgbaImage viewer_frame(const std::string& paths, const render::Camera& camera) {
    const auto ds = dataset::open_dataset({paths});
    viewer::SchedulerOptions o;
    o.cnn = false;
    o.memory_budget = 1ull << 30;
    o.camera = camera;
    viewer::Scheduler scheduler(ds, o);
    const auto end = std::chrono::steady_clock::now() + std::chrono::minutes(2);
    while (!scheduler.idle() && std::chrono::steady_clock::now() < end) {
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    EXPECT_TRUE(scheduler.idle());
    viewer::SceneStyle style;
    style.colour = viewer::colour_settings(render::ColourMode::Rgb, ds.bounds_m.min_z, ds.bounds_m.max_z);
    ThreadPool pool(2);
    viewer::FrameRefiner refiner(std::chrono::milliseconds(0));
    refiner.draw(*scheduler.snapshot(), camera, style, pool);
    auto frame = refiner.draw(*scheduler.snapshot(), camera, style, pool).image;
    EXPECT_TRUE(refiner.refined());
    return frame;
}

render::RgbaImage as_image(const Png& png) { return {png.width, png.height, png.pixels}; }

// --classes/--returns/--intensity keep only the full-resolution points the filter keeps: as many as a
// pass over the tile's records with PointFilter counts; a class absent from the tile draws none.
TEST_F(RenderCommand, FiltersApplyToTheFullResolutionPoints) {
    const std::string args = survey("ky-woodford-county") + " --size 320x240";
    const auto ds = dataset::open_dataset({survey("ky-woodford-county")});
    ASSERT_EQ(ds.tiles.size(), 1u);
    const auto filter = PointFilter::parse("", "last", "10-");
    const auto& tile = ds.tiles[0].tile;
    const auto& format = las::point_format_info(tile.header.point_format);
    std::uint64_t kept = 0;
    const std::size_t n = tile.header.record_length;
    dataset::for_each_record_batch(io::File::open(tile.path()), tile, ThreadPool::shared(),
                                   [&](std::uint64_t, std::span<const std::uint8_t> records) {
                                       for (std::size_t k = 0; k + n <= records.size(); k += n) {
                                           kept += filter.keeps(las::decode_point(records.subspan(k, n), format,
                                                                                  tile.header));
                                       }
                                   });
    EXPECT_GT(kept, 0u);
    EXPECT_LT(kept, tile.header.point_count);
    const auto last = render_json(args + " --returns last --intensity 10-", "last");
    EXPECT_EQ(last.at("full_res_points").get<std::uint64_t>(), kept);
    const auto none = render_json(args + " --classes 7", "none");
    EXPECT_EQ(none.at("full_res_points"), 0);
}

TEST_F(RenderCommand, FullDrawsWhatTheViewerDraws) {
    // The real points over the surface, the surface under them at their height (as the viewer
    // lays the decoded tiles over the heightmaps), the interpolation only where points are missing.
    const std::string args = survey("ky-woodford-county") + " --size 480x360 --threads 2";
    const auto full = render_json(args + " --until full", "full");
    render_json(args + " --until heightmaps", "heightmaps");  // the control: no points
    const auto viewer = viewer_frame(survey("ky-woodford-county"), reported_camera(full));
    const double psnr = render::image_psnr_db(as_image(png("full")), viewer);
    const double control = render::image_psnr_db(as_image(png("heightmaps")), viewer);
    RecordProperty("psnr_db", static_cast<int>(psnr));
    EXPECT_GE(psnr, 40.0) << "the heightmaps stage, the control: " << control;
    EXPECT_LT(control, 30.0);
}

// Compares the rendered image with tests/data/golden/NAME.png: at most `max_fraction` of the
// pixels may differ by more than `tolerance` in some channel (float rounding may move an edge
// or a point by a pixel). With LIDARSCOUT_UPDATE_GOLDEN set, the rendered image becomes the
// reference instead.
void expect_golden(const fs::path& rendered, const std::string& name, int tolerance = 24, double max_fraction = 0.01) {
    const fs::path golden = fs::path(LIDARSCOUT_SOURCE_DIR) / "tests" / "data" / "golden" / (name + ".png");
    if (std::getenv("LIDARSCOUT_UPDATE_GOLDEN")) {
        fs::create_directories(golden.parent_path());
        fs::copy_file(rendered, golden, fs::copy_options::overwrite_existing);
        std::printf("updated %s\n", golden.string().c_str());
        return;
    }
    const Png got = read_png(rendered);
    ASSERT_TRUE(got.ok());
    const Png want = read_png(golden);
    ASSERT_TRUE(want.ok()) << "missing golden image " << golden;
    ASSERT_EQ(got.width, want.width);
    ASSERT_EQ(got.height, want.height);
    std::size_t differing = 0;
    for (std::size_t i = 0; i < got.pixels.size(); ++i) {
        const std::uint32_t a = got.pixels[i], b = want.pixels[i];
        const int d =
            std::max({std::abs(render::red(a) - render::red(b)), std::abs(render::green(a) - render::green(b)),
                      std::abs(render::blue(a) - render::blue(b))});
        differing += d > tolerance;
    }
    EXPECT_LE(static_cast<double>(differing) / got.pixels.size(), max_fraction) << differing << " pixels differ";
}

// (in the survey's US survey feet, as info prints its coordinates: 1587600, 1189450, 450 m)
const char kGoldenCamera[] = "--camera 5208651,3902387.2083333335,1476.375,20,-30 --size 160x120";

TEST_F(RenderCommand, GoldenHeightmapsInElevationColours) {
    std::string out, err;
    ASSERT_EQ(render(survey("ky-woodford-county") + " " + kGoldenCamera + " --until heightmaps --colour elevation",
                     "golden", out, err),
              0)
        << err;
    expect_golden(dir_ / "golden.png", "woodford_heightmaps_elevation");
}

TEST_F(RenderCommand, GoldenFullResolutionInRgb) {
    std::string out, err;
    ASSERT_EQ(render(survey("ky-woodford-county") + " " + kGoldenCamera + " --until full", "golden", out, err), 0)
        << err;
    expect_golden(dir_ / "golden.png", "woodford_full_rgb");
}

TEST_F(RenderCommand, BadArgumentsAreOneLineErrors) {
    const std::string s = survey("ky-woodford-county");
    for (const std::string args : {"--camera 1,2,3", "--camera 1,2,3,4,north", "--camera 1,2,3,4,100", "--size 320",
                                   "--size 0x240", "--size 320xabc", "--colour purple", "--until everything",
                                   "--heightmaps magic", "--memory lots", "--heightmaps cnn --model /nonexistent.pt",
                                   "--classes 256", "--returns second", "--intensity 9-2"}) {
        SCOPED_TRACE(args);
        std::string out, err;
        EXPECT_EQ(render(s + " " + args, "bad", out, err), 1);
        EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
        EXPECT_EQ(err.rfind("lidarscout: ", 0), 0u) << err;
        EXPECT_FALSE(fs::exists(dir_ / "bad.png"));
    }
}

// A class filter draws only its points: on an IGN tile in class colours, ground alone leaves out the
// buildings' red and the vegetation's green, and draws fewer pixels than every class.
TEST_F(RenderCommand, AClassFilterDrawsOnlyItsClasses) {
    const std::string args = survey("ign-lidar-hd-1km/test_semis_2021_0382_6565_LA93_IGN69.laz") +
                             " --size 320x240 --until full --colour classification";
    const auto all = render_json(args, "all");
    const auto ground = render_json(args + " --classes 2", "ground");
    EXPECT_LT(ground.at("full_res_points").get<std::uint64_t>(), all.at("full_res_points").get<std::uint64_t>());
    EXPECT_EQ(ground.at("points_drawn"), "classes 2");
    EXPECT_EQ(all.at("points_drawn"), "all points");
    EXPECT_LT(ground.at("drawn_pixels").get<std::size_t>(), all.at("drawn_pixels").get<std::size_t>());
    const auto palette = render::Palette(render::ColourSettings{.mode = render::ColourMode::Classification});
    const auto count = [](const Png& p, std::uint32_t rgba) {
        return std::count(p.pixels.begin(), p.pixels.end(), rgba);
    };
    const Png a = png("all"), g = png("ground");
    ASSERT_TRUE(a.ok() && g.ok());
    const std::uint32_t building = palette.classification(6), ground_colour = palette.classification(2);
    EXPECT_GT(count(a, building), 100);
    EXPECT_EQ(count(g, building), 0);
    EXPECT_GT(count(g, ground_colour), 100);
}

TEST_F(RenderCommand, CnnHeightmapsWhenTheModelExists) {
    std::string model;
    try {
        model = nn::default_model_path();
    } catch (const std::exception& e) {
        GTEST_SKIP() << "no trained heightmap network yet: " << e.what();
    }
    const auto j = render_json(survey("ky-jmo335-eastern-kentucky") + " --until heightmaps --heightmaps cnn --size " +
                                   "320x240 --colour elevation --model " + model,
                               "cnn");
    EXPECT_EQ(j.at("heightmap_method"), "cnn");
    EXPECT_GT(j.at("patches_with_heightmaps").get<int>(), 10);
    EXPECT_GE(static_cast<double>(drawn_pixels(png("cnn"))) / (320 * 240), 0.35);
}

// A remote tile renders to the same PNG, byte for byte, as the local file (all stages: chunk
// points, heightmaps, full resolution).
TEST_F(RenderCommand, RemoteTileRendersTheSameImageAsTheLocalFile) {
    const std::string rel = "surveys/ky-woodford-county/5205000_3900000.laz";
    std::string out, err;
    ASSERT_EQ(render("--size 320x180 " + (test::data_dir() / rel).string(), "local", out, err), 0) << err;
    ASSERT_EQ(render("--size 320x180 " + test::NginxServer::instance().url(rel), "remote", out, err), 0) << err;
    std::ifstream a(dir_ / "local.png", std::ios::binary), b(dir_ / "remote.png", std::ios::binary);
    const std::string local{std::istreambuf_iterator<char>(a), std::istreambuf_iterator<char>()};
    const std::string remote{std::istreambuf_iterator<char>(b), std::istreambuf_iterator<char>()};
    EXPECT_GT(local.size(), 1000u);
    EXPECT_TRUE(local == remote);
}

TEST_F(RenderCommand, CorruptChunkCostsOnlyItsPoints) {
    const auto tile = test::damaged_tile(dir_).string();
    std::string out, err;
    EXPECT_EQ(render(tile + " --size 160x120 --json", "damaged", out, err), 3) << err;
    EXPECT_TRUE(fs::exists(dir_ / "damaged.png"));
    const auto j = nlohmann::json::parse(out);
    EXPECT_EQ(j.at("full_res_points"), 1'012'412u - test::kDamagedChunkPoints);
    EXPECT_EQ(j.at("points_skipped"), test::kDamagedChunkPoints);
    ASSERT_EQ(j.at("skipped_chunks").size(), 1u) << out;
    const auto cause = j.at("skipped_chunks")[0].at("cause").get<std::string>();
    EXPECT_NE(cause.find(test::kDamagedChunkText), std::string::npos) << cause;
    EXPECT_NE(err.find("skipped " + tile + ": at byte "), std::string::npos) << err;
}

// --camera takes the CRS's units (US feet here, as info prints them), and a camera that sees none
// of the data is an error naming the data's bounds in those units, not a blank PNG.
TEST_F(RenderCommand, CameraInTheCrsUnitsAndACameraThatSeesNothing) {
    std::string out, err;
    const std::string ky = survey("ky-woodford-county") + " --until overview --size 160x120 --camera ";
    EXPECT_EQ(render(ky + "5209000,3904000,3000,0,-90", "feet", out, err), 0) << err;
    EXPECT_EQ(render(ky + "1587700,1189700,900,0,-90", "metres", out, err), 1);
    EXPECT_NE(err.find("sees none of the data, which lies in 5208145.64,3902993.55,5209999.99,3904999.99 "
                       "(xmin,ymin,xmax,ymax in the CRS's units: US survey foot; --camera takes the same units)"),
              std::string::npos) << err;
    EXPECT_FALSE(fs::exists(dir_ / "metres.png"));
}

// A server that answers a tile's header and chunk table, then 404 for everything else: no
// image from nothing, one line and exit status 1.
TEST_F(RenderCommand, EveryChunkPointFailedIsAnError) {
    std::ifstream in(test::data_dir() / "surveys/ky-woodford-county/5205000_3900000.laz", std::ios::binary);
    test::FaultServer server({std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()});
    server.answer_first = 2;  // the head and the tail
    const std::string url = server.url().substr(0, server.url().rfind('/')) + "/tile.laz";  // (any path serves)
    std::string out, err;
    EXPECT_EQ(render("--size 320x180 --cache-size 0 " + url, "failed", out, err), 1);
    EXPECT_NE(err.find("render: every chunk point failed"), std::string::npos) << err;
    EXPECT_NE(err.find("HTTP status 404"), std::string::npos) << err;
}

}  // namespace
}  // namespace lidarscout
