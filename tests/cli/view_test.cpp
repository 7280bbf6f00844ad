// `lidarscout view`: --help without a display, one clear line and exit 1 without one, and under
// Xvfb the demo (generated into a scratch cache folder) and a real survey, each shown until a
// scripted screenshot in which the terrain covers most of the image.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <string>

#include <unistd.h>

#include "render/framebuffer.hpp"
#include "png_test_util.hpp"
#include "test_data.hpp"


namespace lidarscout {
namespace {

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
    int run_xvfb(const std::string& args, std::string& out) const {
        const std::string cmd = "XDG_CACHE_HOME=" + (dir_ / "cache").string() + kLeakCheck +
                                " xvfb-run -a -s '-screen 0 1024x768x24' " LIDARSCOUT_CLI " view " + args + " 2>&1";
        return test::run_command(cmd, out);
    }
    static bool have_xvfb() { return std::system("command -v xvfb-run >/dev/null 2>&1") == 0; }

    fs::path dir_;
};

TEST_F(ViewCommand, HelpNeedsNoDisplay) {
    std::string out;
    EXPECT_EQ(test::run_command("env -u DISPLAY -u WAYLAND_DISPLAY " LIDARSCOUT_CLI " view --help 2>&1", out), 0);
    EXPECT_NE(out.find("--screenshot"), std::string::npos) << out;
}

TEST_F(ViewCommand, NoDisplayIsOneClearLine) {
    std::string out;
    const std::string survey = (test::surveys_dir() / "ky-woodford-county").string();
    EXPECT_EQ(test::run_command("env -u DISPLAY -u WAYLAND_DISPLAY " LIDARSCOUT_CLI " view " + survey + " 2>&1", out), 1);
    EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 1) << out;
    EXPECT_NE(out.find("display"), std::string::npos) << out;
}

TEST_F(ViewCommand, ShowsTheDemo) {
    if (!have_xvfb()) GTEST_SKIP() << "xvfb-run not found (Debian package xvfb)";
    std::string out;
    const fs::path shot = dir_ / "demo.png";
    ASSERT_EQ(run_xvfb("--demo-km 1 --no-cnn --size 480x480 --quit-after 15 --screenshot " + shot.string(), out), 0)
        << out;
    EXPECT_TRUE(fs::exists(dir_ / "cache" / "lidarscout")) << out;
    EXPECT_GT(drawn_share(shot), 0.5) << out;
}

TEST_F(ViewCommand, ShowsASurvey) {
    if (!have_xvfb()) GTEST_SKIP() << "xvfb-run not found (Debian package xvfb)";
    std::string out;
    const fs::path shot = dir_ / "woodford.png";
    const std::string survey = (test::surveys_dir() / "ky-woodford-county").string();
    ASSERT_EQ(run_xvfb(survey + " --no-cnn --size 480x480 --quit-after 10 --screenshot " + shot.string(), out), 0)
        << out;
    EXPECT_GT(drawn_share(shot), 0.5) << out;
}

}  // namespace
}  // namespace lidarscout
