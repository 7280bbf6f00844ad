// The page in a real browser: Debian's chromium, headless, WebGL2 on SwiftShader, driven over its
// DevTools pipe (chromium_page.py), opens the page of `lidarscout serve` for ky-jmo335 at
// #camera=auto; once the page says everything the view wants is in (its #timings hold "idle"), its
// screenshot is compared with `render --camera auto --until full` of the same survey (the same auto
// camera): not blank, at least 0.8 of the pixels render draws are drawn, and a small mean difference
// from render's image. The page's own timings are read back from its DOM (#timings) and printed;
// two scripted clicks with the distance tool on give a point readout and a length. In classification
// mode the page's image is compared with render's of that mode. Skipped only where chromium is
// missing (scripts/setup.sh installs it).
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
#include "test_paths.hpp"

namespace lidarscout::test {
namespace {

const char* kChromium = "/usr/bin/chromium";
// The page against render at the same camera (its heightmaps under the decoded points as render lays
// them; render draws every point, the page the levels a pixel apart): measured 8.1 levels (a blank
// page would differ by about 25 where render draws 38% of the image).
constexpr double kMostMeanDifference = 12;

std::string jmo335() { return (surveys_dir() / "ky-jmo335-eastern-kentucky").string(); }

// The page at `url` in a fresh headless chromium (tests/serve/chromium_page.py, in real time), once its
// #timings say idle (everything the view wants is in; the scripted clicks, if any, made in that frame): its
// screenshot at `shot` (when not empty) and its HTML. Alone the page needs 5-25 s; beside the suite's heaviest
// tests more, so it may take up to 300 s.
std::string open_until_idle(const std::filesystem::path& profile, const std::string& url,
                            const std::filesystem::path& shot = {}) {
    const auto html = profile.parent_path() / (profile.filename().string() + ".html");
    const std::string command = "/usr/bin/python3 '" + std::string(LIDARSCOUT_SOURCE_DIR) +
                                "/tests/serve/chromium_page.py' '" + url + "' --profile '" + profile.string() +
                                "' --html '" + html.string() + "'" +
                                (shot.empty() ? "" : " --screenshot '" + shot.string() + "'");
    EXPECT_EQ(std::system(command.c_str()), 0) << "the page became idle: " << command;
    std::ifstream in(html);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
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
    const auto shot = dir / "page.png", ref = dir / "render.png";
    const std::string page_url = url + "#camera=auto&ui=0";
    open_until_idle(dir / "profile", page_url, shot);
    // (and the cursor readout and distance tool: two clicks on the survey once the page is complete)
    const std::string html = open_until_idle(dir / "profile2", page_url + "&measure=1&clicks=600,400;700,450");
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
    const auto start = html.find("<pre id=\"timings\" hidden=\"\">");
    ASSERT_NE(start, std::string::npos);
    const auto open = html.find('>', start) + 1;
    const auto timings = nlohmann::json::parse(html.substr(open, html.find('<', open) - open));
    std::printf("page timings (ms since navigation): %s\n", timings.dump().c_str());
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
    const auto shot = dir / "page.png", ref = dir / "render.png";
    const std::string page_url = url + "#camera=auto&ui=0&colour=classification";
    open_until_idle(dir / "profile", page_url, shot);
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
