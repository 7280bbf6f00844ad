// scripts/gpu_checks.sh end to end on this machine (--dry-run): the programs of this build tree
// packed as for a GPU machine, every step run, and the summary read back: every case of
// tests/render/gpu_cases.hpp listed in order with its CPU side passed and its GPU side not run
// (no device, or --cpu-only where this machine has one), the plugin's report clean (a plugin that
// was built was opened), bench_raster's frames there, the memcheck and training steps saying why
// they did not run, three files out of the eight a device call brings back; and a bad argument is
// one line with exit status 2.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "render/backend.hpp"
#include "render/gpu_cases.hpp"
#include "temp_dir_fixture.hpp"
#include "test_data.hpp"
#include "test_paths.hpp"

namespace lidarscout {
namespace {

#if LIDARSCOUT_BENCH_BUILT  // (the harness and bench_raster are built with the benchmarks)

namespace fs = std::filesystem;

class GpuChecks : public test::TempDirTest {
protected:
    std::string script() const { return std::string(LIDARSCOUT_SOURCE_DIR) + "/scripts/gpu_checks.sh"; }
};

nlohmann::json read_json(const std::string& path) {
    std::ifstream in(path);
    return nlohmann::json::parse(in);  // our own script's output
}

TEST_F(GpuChecks, DryRunRunsEveryStepAndSummarises) {
    std::string out;
    ASSERT_EQ(test::run_command(script() + " pack --build " + LIDARSCOUT_BUILD_DIR + " --to " + path("carry") + " 2>&1",
                                out),
              0)
        << out;
    EXPECT_NE(out.find("of 67108864"), std::string::npos) << out;
    const int rc = test::run_command(script() + " --dry-run --train --tree " + path("no-tree") + " --from " +
                                         path("carry") + " " + path("out") + " 2>&1",
                                     out);
    ASSERT_EQ(rc, 0) << out;
    EXPECT_NE(out.find("passed: yes"), std::string::npos) << out;

    const nlohmann::json s = read_json(path("out") + "/summary.json");
    EXPECT_EQ(s.at("mode"), "dry run");
    EXPECT_EQ(s.at("passed"), true);
    const nlohmann::json& h = s.at("harness");
    const std::string reason = render::cuda_unavailable_reason();
    const std::string gpu_note = reason.empty() ? "not run: --cpu-only" : "not run: no device";
    const auto cases = render::gpu_cases::cases();
    ASSERT_EQ(h.at("cases").size(), cases.size());
    for (std::size_t i = 0; i < cases.size(); ++i) {
        const nlohmann::json& c = h.at("cases")[i];
        EXPECT_EQ(c.at("name"), std::string(cases[i].name));
        EXPECT_EQ(c.at("cpu").at("status"), "passed") << c.dump();
        EXPECT_EQ(c.at("gpu").at("status"), "not run") << c.dump();
        EXPECT_EQ(c.at("gpu").at("reason"), gpu_note) << c.dump();
    }
    EXPECT_EQ(h.at("plugin").at("clean"), true) << h.at("plugin").dump();
    if (fs::exists(std::string(LIDARSCOUT_BUILD_DIR) + "/liblidarscout_cuda_raster.so")) {
        const std::string plugin = h.at("plugin").at("path").is_string() ? h.at("plugin").at("path") : "";
        const std::string packed = "/bin/liblidarscout_cuda_raster.so";  // the payload's, next to the harness
        EXPECT_EQ(plugin.size() > packed.size() ? plugin.substr(plugin.size() - packed.size()) : plugin, packed);
        EXPECT_EQ(h.at("plugin").at("unavailable").get<std::string>().find("was not built"), std::string::npos);
    }
    std::string steps;
    for (const nlohmann::json& step : s.at("steps")) {
        steps += step.at("name").get<std::string>() + ": " + step.at("status").get<std::string>() + "\n";
    }
    EXPECT_EQ(steps, "unpack: passed\nharness: passed\nbench_raster: passed\nmemcheck: not run: dry run\n"
                     "train: not run: no " + path("no-tree") + "/windows.xz (scripts/train_gpu.sh pack)\n");
    EXPECT_NE(s.at("bench_raster").dump().find("frame of 40 patches"), std::string::npos) << s.at("bench_raster");
    std::size_t files = 0;
    for (const auto& e : fs::recursive_directory_iterator(path("out"))) files += e.is_regular_file();
    EXPECT_EQ(files, 3u);  // summary.md, summary.json, checks.log
    EXPECT_TRUE(fs::exists(path("out") + "/summary.md"));
}

TEST_F(GpuChecks, BadArgumentsAreOneLine) {
    std::string out;
    EXPECT_EQ(test::run_command(script() + " --budget soon " + path("out") + " 2>&1", out), 2);
    EXPECT_EQ(out, "gpu_checks.sh: --budget takes whole seconds, not 'soon'\n");
    EXPECT_EQ(test::run_command(script() + " --from " + path("nothing") + " " + path("out") + " 2>&1", out), 1);
    EXPECT_EQ(out, "gpu_checks.sh: no " + path("nothing") + "/payload.tar.xz (scripts/gpu_checks.sh pack)\n");
    EXPECT_FALSE(fs::exists(path("out")));  // nothing written
}

#endif

}  // namespace
}  // namespace lidarscout
