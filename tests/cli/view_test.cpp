// `lidarscout view`: --help without a display, one clear line and exit 1 without one, and under
// Xvfb the demo (generated into a scratch cache folder) and a real survey, each shown until a
// scripted screenshot in which the terrain covers most of the image; scripted clicks that pick
// two points of a real tile and measure between them; a remote tile list behind nginx and a
// slow link, whose window draws (footprints, progress) before the dataset is open, then the
// overview, with the missing tile listed; a large catalog's footprints in the first frame and its
// centre first; every file of the formats folder opens or is skipped; a tile named twice read once,
// the warning on stderr.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <unistd.h>

#include "delay_proxy.hpp"
#include "nginx_server.hpp"
#include "render/framebuffer.hpp"
#include "png_test_util.hpp"
#include "test_data.hpp"


namespace lidarscout {
namespace {

std::string cli_program() { return LIDARSCOUT_CLI; }

namespace fs = std::filesystem;

// The share of pixels of a PNG that are not the background (-1 when it cannot be read).
double drawn_share(const fs::path& path) {
    const test::Png png = test::read_png(path);
    if (!png.ok()) return -1;
    return static_cast<double>(test::drawn_pixels(png)) / static_cast<double>(png.pixels.size());
}

#if defined(__SANITIZE_ADDRESS__)
// Sanitizer builds: the windowed viewer ends with LeakSanitizer reporting 112 bytes in two
// calloc blocks of a module no longer mapped at exit (no symbols; the OpenGL stack under Xvfb
// loads and unloads its driver); our own code is leak-checked by every other test.
constexpr const char* kLeakCheck = " ASAN_OPTIONS=detect_leaks=0";
#else
constexpr const char* kLeakCheck = "";
#endif

class ViewCommand : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() / ("lidarscout_view_test_" + std::to_string(::getpid()));
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }

    // Runs the viewer under Xvfb with a scratch cache folder; stderr+stdout into `out`.
    // `guard` goes before xvfb-run (e.g. "timeout 300").
    int run_xvfb(const std::string& args, std::string& out, const std::string& guard = "") const {
        const std::string cmd = "XDG_CACHE_HOME=" + (dir_ / "cache").string() + kLeakCheck + " " + guard +
                                " xvfb-run -a -s '-screen 0 1024x768x24' " + LIDARSCOUT_CLI + " view " + args + " 2>&1";
        return test::run_command(cmd, out);
    }
    static bool have_xvfb() { return std::system("command -v xvfb-run >/dev/null 2>&1") == 0; }

    static std::string ign_tile() {
        return (test::surveys_dir() / "ign-lidar-hd-1km/test_semis_2021_0382_6565_LA93_IGN69.laz").string();
    }
    // A session (written to `name` in the scratch folder) of an IGN tile seen from 300 m above its middle.
    fs::path ign_from_above(const std::string& name) const {
        const nlohmann::json s = {{"kind", "lidarscout session"}, {"version", 1}, {"paths", {ign_tile()}},
                                  {"camera", {{"target", {382500, 6564500, 10}}, {"distance", 300}, {"yaw_deg", 0},
                                              {"pitch_deg", -89}, {"fov_deg", 60}}}};
        std::ofstream(dir_ / name) << s.dump();
        return dir_ / name;
    }

    fs::path dir_;
};

TEST_F(ViewCommand, HelpNeedsNoDisplay) {
    std::string out;
    EXPECT_EQ(test::run_command("env -u DISPLAY -u WAYLAND_DISPLAY " + cli_program() + " view --help 2>&1", out), 0);
    EXPECT_NE(out.find("--screenshot"), std::string::npos) << out;
}

TEST_F(ViewCommand, NoDisplayIsOneClearLine) {
    std::string out;
    const std::string survey = (test::surveys_dir() / "ky-woodford-county").string();
    const std::string no_display = "env -u DISPLAY -u WAYLAND_DISPLAY ";
    EXPECT_EQ(test::run_command(no_display + cli_program() + " view " + survey + " 2>&1", out),
              1);
    EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 1) << out;
    EXPECT_NE(out.find("display"), std::string::npos) << out;
}

TEST_F(ViewCommand, ShowsTheDemo) {
    ASSERT_TRUE(have_xvfb()) << "xvfb-run not found (scripts/setup.sh installs the Debian package xvfb)";
    std::string out;
    const fs::path shot = dir_ / "demo.png";
    ASSERT_EQ(run_xvfb("--demo-km 1 --no-cnn --size 480x480 --quit-after 15 --screenshot " + shot.string(), out), 0)
        << out;
    EXPECT_TRUE(fs::exists(dir_ / "cache" / "lidarscout")) << out;
    EXPECT_GT(drawn_share(shot), 0.5) << out;
}

TEST_F(ViewCommand, ShowsASurvey) {
    ASSERT_TRUE(have_xvfb()) << "xvfb-run not found (scripts/setup.sh installs the Debian package xvfb)";
    std::string out;
    const fs::path shot = dir_ / "woodford.png";
    const std::string survey = (test::surveys_dir() / "ky-woodford-county").string();
    ASSERT_EQ(run_xvfb(survey + " --no-cnn --size 480x480 --quit-after 10 --screenshot " + shot.string(), out), 0)
        << out;
    EXPECT_GT(drawn_share(shot), 0.5) << out;
}

TEST_F(ViewCommand, ATileNamedTwiceIsShownOnceWithAWarning) {
    ASSERT_TRUE(have_xvfb()) << "xvfb-run not found (scripts/setup.sh installs the Debian package xvfb)";
    std::string out;
    const std::string twice =
        ign_tile() + " " + (test::surveys_dir() / "ign-lidar-hd-1km/../ign-lidar-hd-1km").string();
    ASSERT_EQ(run_xvfb(twice + " --no-cnn --size 320x240 --quit-after 3", out), 0) << out;
    EXPECT_NE(out.find("lidarscout: warning: 1 input names a tile already named, read once: " + ign_tile() +
                       " (2 times)"), std::string::npos) << out;
}

// "click X,Y: x 1 y 2 z 3 (...": the three coordinates of a scripted click's report.
std::array<double, 3> clicked_xyz(const std::string& out, const std::string& at) {
    const auto line = out.find("click " + at + ": x ");
    if (line == std::string::npos) return {NAN, NAN, NAN};
    std::array<double, 3> xyz{};
    const int n = std::sscanf(out.c_str() + line + at.size() + 8, "x %lf y %lf z %lf", &xyz[0], &xyz[1], &xyz[2]);
    return n == 3 ? xyz : std::array<double, 3>{NAN, NAN, NAN};
}

TEST_F(ViewCommand, ScriptedClicksPickPointsAndMeasureBetweenThem) {
    ASSERT_TRUE(have_xvfb()) << "xvfb-run not found (scripts/setup.sh installs the Debian package xvfb)";
    std::string out;
    const fs::path shot = dir_ / "measure.png";
    const std::string survey = (test::surveys_dir() / "ky-woodford-county").string();
    ASSERT_EQ(run_xvfb(survey + " --no-cnn --size 480x480 --quit-after 8 --measure --click 240,240 --click 300,300 "
                                "--window-screenshot " + shot.string(), out), 0)
        << out;
    const auto a = clicked_xyz(out, "240,240"), b = clicked_xyz(out, "300,300");
    ASSERT_FALSE(std::isnan(a[0]) || std::isnan(b[0])) << out;
    // The tile's header bounds (US survey feet, EPSG:3089; `info` prints them) hold both points.
    for (const auto& p : {a, b}) {
        EXPECT_GE(p[0], 5208145.63) << out;
        EXPECT_LE(p[0], 5210000.00) << out;
        EXPECT_GE(p[1], 3902993.54) << out;
        EXPECT_LE(p[1], 3905000.00) << out;
        EXPECT_GE(p[2], 851.39) << out;
        EXPECT_LE(p[2], 969.45) << out;
    }
    EXPECT_NE(out.find("US survey foot"), std::string::npos) << out;
    EXPECT_NE(out.find("5205000_3900000.laz"), std::string::npos) << out;
    // The measurement, in metres, agrees with the two points given in feet.
    double distance = 0, horizontal = 0, dz = 0;
    const auto m = out.find("measure: ");
    ASSERT_NE(m, std::string::npos) << out;
    ASSERT_EQ(std::sscanf(out.c_str() + m, "measure: distance %lf m, horizontal %lf m, height difference %lf m",
                          &distance, &horizontal, &dz), 3) << out;
    const double foot = 1200.0 / 3937.0;
    EXPECT_NEAR(horizontal, std::hypot(b[0] - a[0], b[1] - a[1]) * foot, 0.01) << out;
    EXPECT_NEAR(dz, (b[2] - a[2]) * foot, 0.01) << out;
    EXPECT_NEAR(distance, std::hypot(horizontal, dz), 0.01) << out;
    EXPECT_GT(horizontal, 10.0) << "two different points: " << out;
    const test::Png png = test::read_png(shot);  // the window with its panels
    ASSERT_TRUE(png.ok());
    EXPECT_EQ(png.width, 480);
}

// The area tool scripted: four clicks on an IGN tile seen from above make a polygon, measured on
// the points clip would write; its horizontal area is the shoelace area of the four points printed.
TEST_F(ViewCommand, ScriptedAreaMeasuresThePolygonClicked) {
    ASSERT_TRUE(have_xvfb()) << "xvfb-run not found (scripts/setup.sh installs the Debian package xvfb)";
    const fs::path in = ign_from_above("area.lidarscout.json");
    std::string out;
    ASSERT_EQ(run_xvfb("--session " + in.string() + " --no-cnn --size 480x480 --quit-after 4 --area --click 140,140 "
                       "--click 340,140 --click 340,340 --click 140,340", out), 0)
        << out;
    std::vector<std::array<double, 3>> v;
    for (const std::string at : {"140,140", "340,140", "340,340", "140,340"}) v.push_back(clicked_xyz(out, at));
    double twice = 0;
    for (std::size_t i = 0, j = 3; i < 4; j = i++) twice += v[j][0] * v[i][1] - v[i][0] * v[j][1];
    double area = 0, cut = 0, fill = 0;
    const auto line = out.find("area: area ");
    ASSERT_NE(line, std::string::npos) << out;
    const char* format = "area: area %lf m2 (surface %*f m2), cut %lf m3, fill %lf m3";
    ASSERT_EQ(std::sscanf(out.c_str() + line, format, &area, &cut, &fill), 3) << out;
    EXPECT_NEAR(area, std::abs(twice) / 2, 0.1) << out;
    EXPECT_GT(area, 1000) << out;
    EXPECT_GT(cut + fill, 0) << out;
}

std::string file_bytes(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// "WHAT: N points written to FILE": N (-1 when the line is missing).
long long points_written(const std::string& out, const std::string& what, const fs::path& file) {
    const std::string tail = " points written to " + file.string();
    const auto end = out.find(tail);
    const auto start = out.rfind(what + ": ", end);
    if (end == std::string::npos || start == std::string::npos) return -1;
    return std::stoll(out.substr(start + what.size() + 2, end - start - what.size() - 2));
}

// A profile opened with --profile (the dataset CRS's units, filtered as drawn) and written once
// read: the CSV and the LAZ are the files `lidarscout profile` writes for the same line, width and
// filter, byte for byte.
TEST_F(ViewCommand, ScriptedProfileIsWhatTheProfileCommandWrites) {
    ASSERT_TRUE(have_xvfb()) << "xvfb-run not found (scripts/setup.sh installs the Debian package xvfb)";
    const std::string tile = (test::surveys_dir() / "ky-woodford-county" / "5205000_3900000.laz").string();
    const std::string line = "5208400.5,3903200.25,5209700,3904700", width = "6";
    for (const std::string ext : {".csv", ".laz"}) {
        SCOPED_TRACE(ext);
        const fs::path viewed = dir_ / ("viewed" + ext), expected = dir_ / ("expected" + ext);
        std::string out;
        ASSERT_EQ(run_xvfb(tile + " --no-cnn --size 480x480 --classes 2,6 --quit-after 1 --profile " + line + "," +
                           width + " --profile-out " + viewed.string(), out, "timeout 300"), 0) << out;
        const long long n = points_written(out, "profile", viewed);
        EXPECT_GT(n, 100) << out;
        std::string cli;
        ASSERT_EQ(test::run_command(cli_program() + " profile " + tile + " --line " + line + " --width " + width +
                                    " --classes 2,6 -o " + expected.string() + " 2>&1", cli), 0) << cli;
        EXPECT_NE(cli.find(std::to_string(n) + " points in a corridor"), std::string::npos) << cli;
        EXPECT_EQ(file_bytes(viewed), file_bytes(expected));
    }
    std::string out;  // refused before a window opens: a width of 0, an output without its profile
    EXPECT_EQ(run_xvfb(tile + " --quit-after 1 --profile " + line + ",0", out), 1) << out;
    EXPECT_NE(out.find("the width must be positive"), std::string::npos) << out;
    EXPECT_EQ(run_xvfb(tile + " --quit-after 1 --profile-out " + (dir_ / "p.csv").string(), out), 1) << out;
    EXPECT_NE(out.find("--profile-out wants --profile"), std::string::npos) << out;
    EXPECT_EQ(run_xvfb(tile + " --quit-after 1 --profile " + line + ",2 --profile-out " + tile, out), 1) << out;
    EXPECT_FALSE(fs::exists(dir_ / "p.csv"));
}

// The area tool's polygon clipped (--clip-out): the LAZ is the file `lidarscout clip --polygon`
// writes for the polygon the viewer prints, byte for byte, and the area tool counts its points.
TEST_F(ViewCommand, ScriptedClipOutIsWhatTheClipCommandWrites) {
    ASSERT_TRUE(have_xvfb()) << "xvfb-run not found (scripts/setup.sh installs the Debian package xvfb)";
    const fs::path in = ign_from_above("clip.lidarscout.json"), viewed = dir_ / "viewed.laz";
    const fs::path expected = dir_ / "expected.laz";
    const std::string tile = ign_tile();
    std::string out;
    ASSERT_EQ(run_xvfb("--session " + in.string() + " --no-cnn --size 480x480 --quit-after 4 --area --click 140,140 "
                       "--click 340,160 --click 300,340 --click 150,300 --clip-out " + viewed.string(), out,
                       "timeout 300"), 0) << out;
    const auto at = out.find("clip polygon: POLYGON ((");
    ASSERT_NE(at, std::string::npos) << out;
    const std::string wkt = out.substr(at + 14, out.find('\n', at) - at - 14);
    const long long n = points_written(out, "clip", viewed);
    EXPECT_GT(n, 1000) << out;
    const auto area = out.find("area: area "), counted = out.find(" points in ", area);
    ASSERT_NE(counted, std::string::npos) << out;
    const auto from = out.rfind("; ", counted) + 2;
    EXPECT_EQ(std::stoll(out.substr(from, counted - from)), n) << "the area tool counts what clip writes\n" << out;
    std::string cli;
    ASSERT_EQ(test::run_command(cli_program() + " clip " + tile + " --polygon '" + wkt + "' -o " + expected.string() +
                                " --json 2>&1", cli), 0) << cli;
    EXPECT_NE(cli.find("\"points_written\": " + std::to_string(n)), std::string::npos) << cli;
    EXPECT_EQ(file_bytes(viewed), file_bytes(expected));
    EXPECT_EQ(run_xvfb(tile + " --quit-after 1 --clip-out " + viewed.string(), out), 1) << out;  // no --area
    EXPECT_NE(out.find("--clip-out wants --area"), std::string::npos) << out;
}

// A session opens as saved (its dataset, camera, filter; the click picks only what the filter
// keeps) and is written back with its labels, measurements and a field this version does not know.
TEST_F(ViewCommand, ASessionOpensAsSavedAndIsWrittenBack) {
    ASSERT_TRUE(have_xvfb()) << "xvfb-run not found (scripts/setup.sh installs the Debian package xvfb)";
    const std::string tile =
        (test::surveys_dir() / "ign-lidar-hd-1km/test_semis_2021_0382_6565_LA93_IGN69.laz").string();
    nlohmann::json s = {{"kind", "lidarscout session"}, {"version", 1}, {"paths", {tile}}, {"crs", ""},
                        {"camera", {{"target", {382500, 6564500, 10}}, {"distance", 300}, {"yaw_deg", 0},
                                    {"pitch_deg", -89}, {"fov_deg", 60}}},
                        {"filter", {{"classes", "6"}, {"returns", ""}, {"intensity", ""}}},
                        {"colour", "classification"},
                        {"measurements", {{{"from", {382400, 6564400, 5}}, {"to", {382600, 6564600, 7}}}}},
                        {"annotations", {{{"at", {382500, 6564500, 10}}, {"text", "the square"}}}},
                        {"profiles", {{{"line", {0, 0, 1, 1}}, {"width", 2}}}}};
    const fs::path in = dir_ / "in.lidarscout.json", back = dir_ / "back.lidarscout.json";
    std::ofstream(in) << s.dump();
    std::string out;
    ASSERT_EQ(run_xvfb("--session " + in.string() + " --no-cnn --size 480x480 --quit-after 4 --click 240,240 "
                       "--click 100,380 --save-session " + back.string(), out), 0)
        << out;
    int buildings = 0;
    for (const std::string at : {"240,240", "100,380"}) {  // buildings only: the picked points are of class 6
        const auto line = out.find("click " + at + ": ");
        ASSERT_NE(line, std::string::npos) << out;
        const std::string text = out.substr(line, out.find('\n', line) - line);
        buildings += text.find("class 6 ") != std::string::npos;
        EXPECT_TRUE(text.find("no point") != std::string::npos || text.find("class 6 ") != std::string::npos) << text;
    }
    EXPECT_GE(buildings, 1) << out;  // a roof under one of the clicks, at least
    const auto saved = nlohmann::json::parse(std::ifstream(back));
    for (const char* key : {"paths", "filter", "colour", "measurements", "annotations", "profiles"}) {
        EXPECT_EQ(saved.at(key), s.at(key)) << key;
    }
    EXPECT_NEAR(saved.at("camera").at("distance").get<double>(), 300, 1e-9);
    EXPECT_NEAR(saved.at("camera").at("target").at(0).get<double>(), 382500, 1e-9);
}

}  // namespace
}  // namespace lidarscout

namespace lidarscout {
namespace {

TEST_F(ViewCommand, RemoteDatasetDrawsBeforeItIsOpenThenTheOverview) {
    ASSERT_TRUE(have_xvfb()) << "xvfb-run not found (scripts/setup.sh installs the Debian package xvfb)";
    auto& server = test::NginxServer::instance();
    const test::DelayProxy proxy(server.port(), std::chrono::milliseconds(150));  // 300 ms round trips
    const std::string list = "view_progressive_" + std::to_string(::getpid()) + ".txt";
    const auto survey = test::surveys_dir() / "ky-jmo335-eastern-kentucky";
    std::size_t tiles = 0;
    {
        std::ofstream out(server.lists_dir() / list);
        for (const auto& f : fs::directory_iterator(survey)) {  // three tiles: quitting waits for reads in flight
            if (f.path().extension() != ".laz" || tiles == 3) continue;
            out << "../surveys/ky-jmo335-eastern-kentucky/" << f.path().filename().string() << "\n";
            ++tiles;
        }
        out << "../surveys/ky-jmo335-eastern-kentucky/missing.laz\n";  // a 404: listed, not fatal
    }
    ASSERT_GT(tiles, 1u);
    const std::string url = "http://127.0.0.1:" + std::to_string(proxy.port()) + "/lists/" + list;
    const fs::path stats = dir_ / "stats.json";
    std::string out;
    ASSERT_EQ(run_xvfb("'" + url + "' --no-cnn --cache-size 0 --size 320x240 --quit-after 1 --stats-json " +
                       stats.string(), out), 0) << out;
    const auto j = test::read_json(stats);
    ASSERT_TRUE(j.at("dataset_open_s").is_number()) << j.dump();
    ASSERT_TRUE(j.at("first_frame_s").is_number()) << j.dump();
    ASSERT_TRUE(j.at("first_overview_s").is_number()) << j.dump();
    EXPECT_GE(j.at("frames_while_opening").get<int>(), 1) << j.dump();
    EXPECT_LT(j.at("first_frame_s").get<double>(), j.at("dataset_open_s").get<double>()) << j.dump();
    EXPECT_GE(j.at("first_overview_s").get<double>(), j.at("dataset_open_s").get<double>()) << j.dump();
    EXPECT_EQ(j.at("tiles").get<std::size_t>(), tiles) << j.dump();
    EXPECT_EQ(j.at("skipped").get<std::size_t>(), 1u) << j.dump();
    // what the reads cost: at least each tile's head and tail (and the list, the missing tile's head)
    const auto requests = j.at("requests").get<std::uint64_t>();
    EXPECT_GE(requests, 2 * tiles + 2) << j.dump();
    EXPECT_DOUBLE_EQ(j.at("requests_per_tile").get<double>(), static_cast<double>(requests) / tiles) << j.dump();
    EXPECT_GT(j.at("bytes").get<std::uint64_t>(), 2 * tiles * 2048) << j.dump();
    fs::remove(server.lists_dir() / list);
}

// A catalog of 72 items (one IGN tile copied onto a 9x8 grid, as files): every footprint is in the first
// frame, and its centre opens first as a preview, which the window draws until the dataset's own terrain
// shows: here to the end, as these tiles have too few chunk points for any heightmap.
TEST_F(ViewCommand, ALargeCatalogShowsEveryFootprintFirstThenItsCentre) {
    if (!have_xvfb()) GTEST_SKIP() << "xvfb-run is missing: scripts/setup.sh installs it";
    const auto tile = (test::surveys_dir() / "ign-lidar-hd-1km/Semis_2022_0906_6665_LA93_IGN69_ok.laz").string();
    const fs::path rep = dir_ / "rep", vpc = dir_ / "rep.vpc", stats = dir_ / "stats.json";
    std::string out;
    ASSERT_EQ(test::run_command(std::string(LIDARSCOUT_CLI) + " synth replicate " + tile + " --grid 9x8 -o " +
                                    rep.string() + " 2>&1", out), 0) << out;
    ASSERT_EQ(test::run_command(std::string(LIDARSCOUT_CLI) + " catalog " + rep.string() + " -o " + vpc.string() +
                                    " 2>&1", out), 0) << out;
    ASSERT_EQ(run_xvfb(vpc.string() + " --no-cnn --size 320x240 --quit-after 1 --stats-json " + stats.string(), out),
              0) << out;
    const auto j = test::read_json(stats);
    ASSERT_TRUE(j.at("footprints_s").is_number()) << j.dump();
    EXPECT_EQ(j.at("footprints_s").get<double>(), j.at("first_frame_s").get<double>()) << j.dump();
    EXPECT_EQ(j.at("tiles").get<std::size_t>(), 72u) << j.dump();  // (too few chunk points for a heightmap)
}

// Seen from 300 m above its middle, the IGN tile is the one nearest the camera: --stats-json times the first frame
// with it whole at full resolution, after the dataset opened (null had it never come).
TEST_F(ViewCommand, TheStatsTimeTheTileNearestTheCameraAtFullResolution) {
    ASSERT_TRUE(have_xvfb()) << "xvfb-run not found (scripts/setup.sh installs the Debian package xvfb)";
    const fs::path stats = dir_ / "stats.json";
    std::string out;
    ASSERT_EQ(run_xvfb("--session " + ign_from_above("near.lidarscout.json").string() +
                       " --no-cnn --size 320x240 --memory 1G --quit-after 6 --stats-json " + stats.string(), out),
              0) << out;
    const auto j = test::read_json(stats);
    ASSERT_TRUE(j.at("nearest_full_s").is_number()) << j.dump();
    EXPECT_GE(j.at("nearest_full_s").get<double>(), j.at("dataset_open_s").get<double>()) << j.dump();
}

// The 35 KB pdrf6 file (bounds +-2.1e9 m) and the whole formats folder hung in the scheduler,
// past 3 GB: each now opens (the hostile files skipped and counted) and the session ends. The
// `timeout` only guards against a hang (exit 124); nothing here is timed.
TEST_F(ViewCommand, EveryFormatsFileOpensOrIsSkipped) {
    ASSERT_TRUE(have_xvfb()) << "xvfb-run not found (scripts/setup.sh installs the Debian package xvfb)";
    const std::string pdrf6 =
        (test::formats_dir() / "visgl__loaders.gl/modules__las__test__data__pdrf6-1.4.laz").string();
    for (const std::string& input : {pdrf6, test::formats_dir().string()}) {
        SCOPED_TRACE(input);
        std::string out;
        const fs::path stats = dir_ / "stats.json";
        fs::remove(stats);
        ASSERT_EQ(run_xvfb("--no-cnn --size 320x240 --quit-after 1 --stats-json " + stats.string() + " " + input,
                           out, "timeout 300"), 0) << out;
        const auto j = test::read_json(stats);
        ASSERT_TRUE(j.at("dataset_open_s").is_number()) << j.dump();
        EXPECT_GE(j.at("tiles").get<std::size_t>(), 1u) << j.dump();
    }
}

// A session whose numbers are out of range is one line naming the file, the field and the range,
// before a window opens (issue 53: a camera distance of 1e300 opened an empty view); a yaw past a
// turn is read wrapped, with a note.
TEST_F(ViewCommand, ASessionOutOfRangeIsOneLineBeforeAWindow) {
    nlohmann::json s = nlohmann::json::parse(std::ifstream(ign_from_above("far.lidarscout.json")));
    s["camera"]["distance"] = 1e300;
    std::ofstream(dir_ / "far.lidarscout.json") << s.dump();
    std::string out;
    const std::string far = (dir_ / "far.lidarscout.json").string();
    EXPECT_EQ(test::run_command("DISPLAY= " + cli_program() + " view --session " + far + " 2>&1", out), 1);
    EXPECT_EQ(out, "lidarscout: " + far + ": camera: \"distance\" is 1e+300, outside the range 1 to 5e+06 "
                   "(metres)\n");
    s["camera"]["distance"] = 300;
    s["camera"]["yaw_deg"] = 725;
    std::ofstream(dir_ / "far.lidarscout.json") << s.dump();
    EXPECT_EQ(test::run_command("DISPLAY= " + cli_program() + " view --session " + far + " 2>&1", out), 1);
    EXPECT_NE(out.find("lidarscout: note: " + far + ": camera: \"yaw_deg\" 725 is read as 5 (the same heading, "
                       "from -180 to 180)\n"), std::string::npos) << out;
}

// A model file that is not a TorchScript model is named before a window opens (no display
// needed); inputs that are all unreadable are each named in the one line the viewer ends with.
TEST_F(ViewCommand, BadModelAndUnreadableInputsAreNamed) {
    const std::string survey = (test::surveys_dir() / "ky-woodford-county").string();
    std::ofstream(dir_ / "bad.pt") << "not a model";
    std::string out;
    const std::string bad = (dir_ / "bad.pt").string();
    EXPECT_EQ(test::run_command("DISPLAY= " + cli_program() + " view " + survey + " --model " + bad + " 2>&1", out), 1);
    EXPECT_NE(out.find("bad.pt: at byte 0: not a TorchScript model"), std::string::npos) << out;
    ASSERT_TRUE(have_xvfb()) << "xvfb-run not found (scripts/setup.sh installs the Debian package xvfb)";
    std::ofstream(dir_ / "pts.csv") << "x,y,z\n1,2,3\n";
    const int status = run_xvfb((dir_ / "pts.csv").string() + " /nonexistent/a.laz --quit-after 2", out);
    // (xvfb-run itself sometimes exits 5 when the viewer ends this fast: "problem while cleaning up")
    const bool xvfb_cleanup = out.find("xvfb-run: error: problem while cleaning up") != std::string::npos;
    EXPECT_TRUE(status == 1 || (xvfb_cleanup && status == 5)) << status << ": " << out;
    EXPECT_NE(out.find("view: no readable LAS/LAZ tile in the given paths: "), std::string::npos) << out;
    EXPECT_NE(out.find("pts.csv: not a LAS/LAZ file nor a tile list"), std::string::npos) << out;
    EXPECT_NE(out.find("/nonexistent/a.laz: no such file or folder"), std::string::npos) << out;
}

}  // namespace
}  // namespace lidarscout
