// The page in a real browser: Debian's chromium, headless, WebGL2 on SwiftShader, opens the page of
// `lidarscout serve` for ky-jmo335 at #camera=auto and its screenshot is compared with
// `render --camera auto --until full` of the same survey (the same auto camera): not blank, at
// least 0.8 of the pixels render draws are drawn, and a small mean difference from render's image.
// The page's own timings are read back from its DOM (#timings) and printed; nothing asserts on
// them; two scripted clicks with the distance tool on give a point readout and a length. In
// classification mode the page's image is compared with render's of that mode. Skipped
// only where chromium is missing (scripts/setup.sh installs it).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>

#include <nlohmann/json.hpp>

#include "png_test_util.hpp"
#include "serve_fixture.hpp"
#include "temp_dir_fixture.hpp"

namespace lidarscout::test {
namespace {

const char* kChromium = "/usr/bin/chromium";
// The page against render at the same camera (its heightmaps under the decoded points as render lays
// them; render draws every point, the page the levels a pixel apart): measured 8.1 levels (a blank
// page would differ by about 25 where render draws 38% of the image).
constexpr double kMostMeanDifference = 12;

std::string jmo335() { return (surveys_dir() / "ky-jmo335-eastern-kentucky").string(); }

// chromium headless with SwiftShader's WebGL2 at 1280 x 720 (render's default size); `what` is
// --screenshot=FILE or --dump-dom. The virtual time budget lets the page stream and draw.
std::string chromium(const std::string& what, const std::string& url, const std::filesystem::path& out) {
    return std::string(kChromium) + " --headless --no-sandbox --use-angle=swiftshader --enable-unsafe-swiftshader "
           "--hide-scrollbars --window-size=1280,720 --virtual-time-budget=60000 --user-data-dir='" +
           (out.parent_path() / "profile").string() + "' " + what + " '" + url + "' >'" + out.string() +
           ".out' 2>/dev/null";
}

// The mean absolute difference of the R, G and B channels of two images of one size, in levels.
double mean_channel_difference(const Png& a, const Png& b) {
    double sum = 0;
    for (std::size_t i = 0; i < a.pixels.size(); ++i) {
        for (int ch = 0; ch < 3; ++ch) {
            sum += std::abs(static_cast<int>((a.pixels[i] >> (8 * ch)) & 0xff) -
                            static_cast<int>((b.pixels[i] >> (8 * ch)) & 0xff));
        }
    }
    return sum / (3.0 * static_cast<double>(a.pixels.size()));
}

std::string read_text(const std::filesystem::path& p) {
    std::ifstream in(p);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

class ServeBrowser : public TempDirTest {
protected:
    void SetUp() override {
        if (!std::filesystem::exists(kChromium)) GTEST_SKIP() << "no chromium (scripts/setup.sh installs it)";
        TempDirTest::SetUp();
    }
};

TEST_F(ServeBrowser, AutoCameraCoversWhatRenderCovers) {
    ServeChild server("'" + jmo335() + "'");
    const std::string url = server.url();
    ASSERT_EQ(url.rfind("http://127.0.0.1:", 0), 0u) << url;
    ASSERT_TRUE(ServeChild::wait_loaded(url)) << "the survey loaded";
    const auto shot = dir / "page.png", ref = dir / "render.png", dom = dir / "dom.html";
    const std::string page_url = url + "#camera=auto&ui=0";
    ASSERT_EQ(std::system(chromium("--screenshot='" + shot.string() + "'", page_url, shot).c_str()), 0);
    // (and the cursor readout and distance tool: two clicks on the survey once the page is complete)
    ASSERT_EQ(std::system(chromium("--dump-dom", page_url + "&measure=1&clicks=600,400;700,450", dom).c_str()), 0);
    ASSERT_EQ(std::system(("'" + std::string(LIDARSCOUT_CLI) + "' render '" + jmo335() +
                           "' --camera auto --until full -o '" + ref.string() + "' 2>/dev/null").c_str()),
              0);
    const Png page = read_png(shot), rendered = read_png(ref);
    ASSERT_TRUE(page.ok());
    ASSERT_TRUE(rendered.ok());
    ASSERT_EQ(page.width, rendered.width);
    ASSERT_EQ(page.height, rendered.height);
    const double total = static_cast<double>(page.width) * page.height;
    const std::size_t drawn = drawn_pixels(page), expected = drawn_pixels(rendered);
    std::printf("page draws %.3f of the image, render %.3f: ratio %.3f\n", drawn / total, expected / total,
                static_cast<double>(drawn) / expected);
    EXPECT_GT(drawn, total * 0.05);  // not blank
    EXPECT_GE(static_cast<double>(drawn), 0.8 * expected);
    EXPECT_LE(static_cast<double>(drawn), 1.25 * expected);  // nor drawn where render sees nothing
    // and what is drawn looks alike: the mean difference per channel over the whole image
    const double difference = mean_channel_difference(page, rendered);
    std::printf("mean difference per channel from render's image: %.2f levels\n", difference);
    EXPECT_LT(difference, kMostMeanDifference);
    // The page's own account of what it loaded (#timings, JSON).
    const std::string html = read_text(dom.string() + ".out");
    const auto start = html.find("<pre id=\"timings\" hidden=\"\">");
    ASSERT_NE(start, std::string::npos);
    const auto open = html.find('>', start) + 1;
    const auto timings = nlohmann::json::parse(html.substr(open, html.find('<', open) - open));
    std::printf("page timings (ms since navigation, virtual time): %s\n", timings.dump().c_str());
    EXPECT_EQ(timings.at("errors"), 0);
    EXPECT_GT(timings.at("points").get<int>(), 0);
    EXPECT_GT(timings.at("patches").get<int>(), 0);
    EXPECT_GT(timings.at("cnn_patches").get<int>(), 0);  // then the network's (the shipped model)
    EXPECT_TRUE(timings.contains("overview"));
    EXPECT_TRUE(timings.contains("first_terrain"));
    EXPECT_NE(html.find("<div id=\"pick\">point 56"), std::string::npos);  // x in feet: 5,67x,xxx
    const auto measured = html.find("<div id=\"measured\">measure: ");
    ASSERT_NE(measured, std::string::npos);
    const auto total_at = html.find("total ", measured);
    ASSERT_NE(total_at, std::string::npos);
    const double length = std::stod(html.substr(total_at + 6, 20));
    std::printf("measured between the two clicks: %.2f ft\n", length);
    EXPECT_GT(length, 100.0);  // 100 px apart at ~8,000 ft: hundreds of feet
    EXPECT_LT(length, 5000.0);
}

// In classification mode the page's heightmaps are render's untextured grey, not the terrain's RGB
// (which showed green between the grey points of its levels of detail, where render, drawing every
// point, hides its surface): measured 2.95 levels a channel from render's image (5.3 with the RGB).
TEST_F(ServeBrowser, ClassificationModeLooksLikeRender) {
    ServeChild server("'" + jmo335() + "'");
    const std::string url = server.url();
    ASSERT_EQ(url.rfind("http://127.0.0.1:", 0), 0u) << url;
    ASSERT_TRUE(ServeChild::wait_loaded(url)) << "the survey loaded";
    const auto shot = dir / "page.png", ref = dir / "render.png";
    const std::string page_url = url + "#camera=auto&ui=0&colour=classification";
    ASSERT_EQ(std::system(chromium("--screenshot='" + shot.string() + "'", page_url, shot).c_str()), 0);
    ASSERT_EQ(std::system(("'" + std::string(LIDARSCOUT_CLI) + "' render '" + jmo335() +
                           "' --camera auto --until full --colour classification -o '" + ref.string() +
                           "' 2>/dev/null").c_str()),
              0);
    const Png page = read_png(shot), rendered = read_png(ref);
    ASSERT_TRUE(page.ok() && rendered.ok());
    ASSERT_EQ(page.pixels.size(), rendered.pixels.size());
    const double difference = mean_channel_difference(page, rendered);
    std::printf("classification mode: mean difference per channel from render's image: %.2f levels\n", difference);
    EXPECT_LT(difference, 4.0);
}

}  // namespace
}  // namespace lidarscout::test
