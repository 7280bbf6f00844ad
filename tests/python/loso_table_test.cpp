// python/lidarscout_train/loso.py `table` (used by scripts/loso_eval.sh and
// scripts/compare_models.sh): the released and shipped columns come from evals of the same
// patches in other folders, the ratios and survey means are computed from them, and an eval of
// other patches (a different linear RMSE) is refused instead of being put beside the others.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "test_data.hpp"

namespace lidarscout {
namespace {

namespace fs = std::filesystem;

// An `eval --json` result of one survey: linear plus one more method.
void write_eval(const fs::path& path, double linear, const std::string& method, double rmse) {
    const nlohmann::json e = {{"methods",
                               {{"linear", {{"patches", 10}, {"rmse_m_mean", linear}}},
                                {method, {{"patches", 10}, {"rmse_m_mean", rmse}}}}}};
    fs::create_directories(path.parent_path());
    std::ofstream(path) << e.dump();
}

int run_table(const fs::path& dir, const std::string& args, std::string& out) {
    const auto python = fs::path(LIDARSCOUT_SOURCE_DIR) / "python";
    return test::run_command("cd " + python.string() + " && /usr/bin/python3 -m lidarscout_train.loso table " + args +
                                 " --shipped-dir " + (dir / "shipped").string() + " --released-dir " +
                                 (dir / "released").string() + " --json " + (dir / "table.json").string() + " 2>&1",
                             out);
}

TEST(LosoTable, ShippedAndReleasedColumnsFromTheSamePatches) {
    const fs::path dir = fs::temp_directory_path() / ("lidarscout_loso_table_" + std::to_string(::getpid()));
    for (const auto* s : {"a", "b"}) {
        const double linear = s[0] == 'a' ? 4.0 : 2.0;
        write_eval(dir / "candidate" / (std::string(s) + ".json"), linear, "cnn", 0.9 * linear);
        write_eval(dir / "shipped" / (std::string(s) + ".json"), linear, "cnn", (s[0] == 'a' ? 1.1 : 0.7) * linear);
        write_eval(dir / "released" / (std::string(s) + ".json"), linear, "released", 0.8 * linear);
    }
    std::string out;
    const std::string both = (dir / "candidate" / "a.json").string() + " " + (dir / "candidate" / "b.json").string();
    ASSERT_EQ(run_table(dir, both, out), 0) << out;
    EXPECT_NE(out.find("shipped CNN / linear"), std::string::npos) << out;
    const auto table = nlohmann::json::parse(std::ifstream(dir / "table.json"));
    EXPECT_NEAR(table.at("mean_cnn_ratio").get<double>(), 0.9, 1e-9);
    EXPECT_NEAR(table.at("mean_shipped_ratio").get<double>(), 0.9, 1e-9);  // (1.1 + 0.7) / 2
    EXPECT_NEAR(table.at("mean_released_ratio").get<double>(), 0.8, 1e-9);
    EXPECT_NEAR(table.at("rows")[0].at("shipped_ratio").get<double>(), 1.1, 1e-9);

    // The shipped model scored other patches of survey b: refused, naming the file.
    write_eval(dir / "shipped" / "b.json", 2.5, "cnn", 2.0);
    EXPECT_NE(run_table(dir, (dir / "candidate" / "b.json").string(), out), 0) << out;
    EXPECT_NE(out.find("not the same patches"), std::string::npos) << out;
    fs::remove_all(dir);
}

}  // namespace
}  // namespace lidarscout
