// A failed command with --json prints one valid JSON object with an `error` on stdout (scripts
// never parse an empty answer), beside its one line on stderr; usage errors too.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "test_data.hpp"

namespace lidarscout {
namespace {

nlohmann::json error_of(const std::string& args, int& status) {
    std::string out;
    status = test::run_command(std::string(LIDARSCOUT_CLI) + " " + args + " 2>/dev/null", out);
    return nlohmann::json::parse(out).at("error");
}

TEST(FailureOutput, EveryCommandThatFailsPrintsAJsonError) {
    for (const std::string args : {"render /nonexistent/a.laz -o /tmp/x.png", "dem /nonexistent/a.laz -o /tmp/x.tif",
                                   "convert /nonexistent/a.laz /tmp/x.laz", "eval /nonexistent/a.laz",
                                   "train-data /nonexistent/a.laz -o /tmp/x.bin",
                                   "synth replicate /nonexistent/a.laz -o /tmp/rep --grid 2x2",
                                   "synth terrain -o /proc/self/demo --km 0.5"}) {
        int status = 0;
        const nlohmann::json e = error_of(args + " --json", status);
        EXPECT_NE(status, 0) << args;
        EXPECT_FALSE(e.at("message").get<std::string>().empty()) << args;
        EXPECT_TRUE(e.at("kind") == "input" || e.at("kind") == "usage") << args << ": " << e.dump();
    }
}

TEST(FailureOutput, UsageErrorsAndNegativeCountsAreNamed) {
    int status = 0;
    auto e = error_of("eval /nonexistent/a.laz --seed -1 --json", status);
    EXPECT_NE(status, 0);
    EXPECT_EQ(e.at("kind"), "usage");
    EXPECT_EQ(e.at("message"), "eval: --seed: expects a whole number 0 or more, not '-1'");
    EXPECT_EQ(status, 1);
    const std::string tile = (test::formats_dir() / "laz-rs__laz-rs/tests__data__point-time-color.las").string();
    e = error_of("convert " + tile + " /tmp/x.laz --format 2.5 --json", status);
    EXPECT_NE(e.at("message").get<std::string>().find("--format: expects a whole number, not '2.5'"),
              std::string::npos) << e.dump();
    e = error_of("convert " + tile + " /tmp/x.laz --format 11 --json", status);
    EXPECT_NE(e.at("message").get<std::string>().find("not in range 0 to 10"), std::string::npos) << e.dump();
    std::string out;  // the control: without --json, stdout stays empty
    EXPECT_NE(test::run_command(std::string(LIDARSCOUT_CLI) + " eval x --seed -1 2>/dev/null", out), 0);
    EXPECT_EQ(out, "");
}

// The sharp edges of issue 28: no command lists the commands; a positive option says its range
// in plain numbers (CLI11 printed the largest double, 309 digits); a benchmark's --help and its
// errors are one line each, never an abort.
TEST(FailureOutput, SharpEdgesAreOneClearLine) {
    std::string out;
    EXPECT_EQ(test::run_command(std::string(LIDARSCOUT_CLI) + " 2>&1", out), 1);
    EXPECT_NE(out.find("Subcommands:"), std::string::npos) << out;
    EXPECT_NE(out.find("render"), std::string::npos) << out;
    EXPECT_EQ(test::run_command(std::string(LIDARSCOUT_CLI) + " dem x.laz -o x.tif --texel 0 2>&1", out), 1);
    EXPECT_NE(out.find("--texel: must be more than 0, not '0'"), std::string::npos) << out;
    EXPECT_LT(out.size(), 200u) << out;
#if LIDARSCOUT_BENCH_BUILT
    const std::string bench_dem = std::string(LIDARSCOUT_BUILD_DIR) + "/bench/bench_dem";
    EXPECT_EQ(test::run_command(bench_dem + " --help 2>&1", out), 0);
    EXPECT_EQ(out.rfind("Usage: bench_dem ", 0), 0u) << out;
    EXPECT_EQ(test::run_command(bench_dem + " /nonexistent/a.laz --runs 1 2>&1", out), 1);
    EXPECT_EQ(out.rfind("bench_dem: ", 0), 0u) << out;
    EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 1) << out;
#endif
}

// A path that is not UTF-8 (a tile list naming one) comes back in the JSON answer with U+FFFD where its bytes were;
// it had made `scan --json` an internal error (the JSON library refuses to write such text).
TEST(FailureOutput, TextThatIsNotUtf8IsReplacedNotAnInternalError) {
    const std::filesystem::path list =
        std::filesystem::temp_directory_path() / ("lidarscout_not_utf8_" + std::to_string(::getpid()) + ".txt");
    const std::string tile = (test::surveys_dir() / "ky-jmo335-eastern-kentucky" / "N117E379.laz").string();
    std::ofstream(list) << "/nonexistent/no\xA5such.laz\n" << tile << "\n";
    std::string out;
    const int status =
        test::run_command(std::string(LIDARSCOUT_CLI) + " scan --json " + list.string() + " 2>/dev/null", out);
    std::filesystem::remove(list);
    EXPECT_EQ(status, 0) << out;
    const auto j = nlohmann::json::parse(out, nullptr, false);
    ASSERT_FALSE(j.is_discarded()) << out;
    ASSERT_EQ(j.at("skipped").size(), 1u) << out;
    const std::string error = j.at("skipped")[0].at("error");
    EXPECT_NE(error.find("no\xEF\xBF\xBDsuch.laz"), std::string::npos) << error;
    EXPECT_EQ(j.at("tiles"), 1) << out;
}

}  // namespace
}  // namespace lidarscout
