// `lidarscout eval --json`: all four methods per dataset and overall, deterministic for a
// seed, colour scored only where the survey has colour, and the ordering every survey shows
// (linear interpolation beats the nearest chunk point).
#include <gtest/gtest.h>

#include <algorithm>

#include "test_data.hpp"

namespace lidarscout {
namespace {

nlohmann::json eval_json(const std::string& args) {
    std::string out;
    const int status = test::run_command(std::string(LIDARSCOUT_CLI) + " eval --json " + args + " 2>/dev/null", out);
    EXPECT_EQ(status, 0);
    return nlohmann::json::parse(out);
}

TEST(EvalCommand, KentuckyAndIgnAllMethodsDeterministic) {
    const std::string args = "--patches 8 --seed 3 " + (test::surveys_dir() / "ky-jmo335-eastern-kentucky").string() +
                             " " + (test::surveys_dir() / "ign-lidar-hd-1km").string();
    const auto a = eval_json(args);
    for (const char* m : {"nearest", "linear", "cubic", "splat"}) {
        SCOPED_TRACE(m);
        const auto& overall = a.at("methods").at(m);
        EXPECT_GT(overall.at("patches").get<int>(), 8);
        EXPECT_GT(overall.at("rmse_m_mean").get<double>(), 0.0);
        EXPECT_GT(overall.at("ms_per_patch_median").get<double>(), 0.0);
        const auto& ky = a.at("datasets").at("ky-jmo335-eastern-kentucky").at("methods").at(m);
        EXPECT_EQ(ky.at("patches").get<int>(), 8);
        EXPECT_GT(ky.at("psnr_db_mean").get<double>(), 10.0);  // Kentucky has colour
        EXPECT_LT(ky.at("psnr_db_mean").get<double>(), 60.0);
        EXPECT_TRUE(
            a.at("datasets").at("ign-lidar-hd-1km").at("methods").at(m).at("psnr_db_mean").is_null());  // no colour
    }
    for (const char* d : {"ky-jmo335-eastern-kentucky", "ign-lidar-hd-1km"}) {
        const auto& ms = a.at("datasets").at(d).at("methods");
        EXPECT_LT(ms.at("linear").at("rmse_m_mean").get<double>(), ms.at("nearest").at("rmse_m_mean").get<double>())
            << d;
    }
    const auto b = eval_json(args);
    for (const char* m : {"nearest", "linear", "cubic", "splat"}) {
        EXPECT_EQ(a.at("methods").at(m).at("rmse_m_mean"), b.at("methods").at(m).at("rmse_m_mean")) << m;
        EXPECT_EQ(a.at("methods").at(m).at("psnr_db_mean"), b.at("methods").at(m).at("psnr_db_mean")) << m;
    }
}

// --split: the two sides score disjoint patches; the windows that straddle both are in neither.
TEST(EvalCommand, SplitSidesAreDisjoint) {
    const std::string ky = (test::surveys_dir() / "ky-jmo335-eastern-kentucky").string();
    const std::string common = "--methods linear --texel 2.5 --patches 1000 --split-block 700 " + ky;
    const auto all = eval_json(common);
    const auto train = eval_json("--split train " + common);
    const auto val = eval_json("--split validation " + common);
    const auto patches = [](const nlohmann::json& j) { return j.at("methods").at("linear").at("patches").get<int>(); };
    const auto& d = [](const nlohmann::json& j) -> const nlohmann::json& {
        return j.at("datasets").at("ky-jmo335-eastern-kentucky");
    };
    ASSERT_GT(patches(train), 10);
    ASSERT_GT(patches(val), 10);
    EXPECT_LT(patches(train) + patches(val), patches(all));  // some windows straddle
    EXPECT_EQ(d(train).at("other_split").get<int>(), patches(all) - patches(train));
    EXPECT_EQ(d(val).at("other_split").get<int>(), patches(all) - patches(val));
    EXPECT_EQ(d(all).at("other_split").get<int>(), 0);
    EXPECT_EQ(val.at("split"), "validation");
}

// --offsets adds shifted lattices: more patches from a small survey.
TEST(EvalCommand, OffsetsAddPatches) {
    const std::string wf =
        "--methods nearest --texel 5 --patches 1000 " + (test::surveys_dir() / "ky-woodford-county").string();
    const auto one = eval_json(wf);
    const auto four = eval_json("--offsets 4 " + wf);
    EXPECT_GT(four.at("methods").at("nearest").at("patches").get<int>(),
              2 * one.at("methods").at("nearest").at("patches").get<int>());
}

TEST(EvalCommand, BadArgumentsAreOneLine) {
    std::string out;
    const auto ky = (test::surveys_dir() / "ky-woodford-county").string();
    EXPECT_EQ(test::run_command(std::string(LIDARSCOUT_CLI) + " eval --methods linear,bogus " + ky + " 2>&1", out), 1);
    EXPECT_NE(out.find("bogus"), std::string::npos);
    EXPECT_EQ(test::run_command(std::string(LIDARSCOUT_CLI) + " eval --stride 0 " + ky + " 2>&1", out), 1);
    EXPECT_NE(out.find("--stride"), std::string::npos);
    EXPECT_EQ(test::run_command(std::string(LIDARSCOUT_CLI) + " eval --split test " + ky + " 2>&1", out), 1);
    EXPECT_NE(out.find("--split"), std::string::npos);
    EXPECT_EQ(test::run_command(
                  std::string(LIDARSCOUT_CLI) + " eval --methods cnn --model /nonexistent.pt " + ky + " 2>&1", out),
              1);
    EXPECT_NE(out.find("/nonexistent.pt"), std::string::npos);
    EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 1) << out;
}

TEST(EvalCommand, ReleasedMethodNeedsItsModel) {
    std::string out;
    const auto ky = (test::surveys_dir() / "ky-woodford-county").string();
    const std::string eval = std::string(LIDARSCOUT_CLI) + " eval --methods linear,released ";
    EXPECT_EQ(test::run_command(eval + ky + " 2>&1", out), 1);
    EXPECT_NE(out.find("--released-model"), std::string::npos) << out;
    EXPECT_EQ(test::run_command(eval + "--released-model /nonexistent/ipes_cnn.pt " + ky + " 2>&1", out), 1);
    EXPECT_NE(out.find("/nonexistent/ipes_cnn.pt"), std::string::npos) << out;
}

// An evaluation that scores no patch is an error with each dataset's counts, not an empty table.
TEST(EvalCommand, NoScoredPatchIsAnErrorThatSaysWhy) {
    std::string out;
    EXPECT_EQ(test::run_command(std::string(LIDARSCOUT_CLI) + " eval " +
                                    (test::surveys_dir() / "ky-woodford-county").string() + " --texel 0.001 2>&1",
                                out), 1);
    EXPECT_NE(out.find("no patch could be scored at --texel 0.001 (patches are 64 texels): ky-woodford-county: "
                       "21 candidate patches, 21 with too few chunk points"), std::string::npos) << out;
}

}  // namespace
}  // namespace lidarscout
