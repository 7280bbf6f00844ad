// `cmake --install` into a temporary prefix gives a program that runs without the source or
// build tree: `info` and `render` with the network (plugin in lib/lidarscout, model in
// share/lidarscout/models) work from there, and `--version` names the version and revision.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>

#include "test_data.hpp"

namespace lidarscout {
namespace {

namespace fs = std::filesystem;

TEST(Install, InstalledProgramFindsItsPluginAndModel) {
    const fs::path prefix = fs::temp_directory_path() / ("lidarscout_install_" + std::to_string(::getpid()));
    std::string out;
    const std::string install = std::string("cmake --install ") + LIDARSCOUT_BUILD_DIR;
    ASSERT_EQ(test::run_command(install + " --prefix " + prefix.string() + " 2>&1", out), 0) << out;
    EXPECT_TRUE(fs::is_regular_file(prefix / "bin/lidarscout"));
    EXPECT_TRUE(fs::is_regular_file(prefix / "lib/lidarscout/liblidarscout_torch.so"));
    EXPECT_TRUE(fs::is_regular_file(prefix / "share/lidarscout/models/heightmap_cnn.pt"));
    EXPECT_TRUE(fs::is_regular_file(prefix / "share/applications/lidarscout.desktop"));
    EXPECT_TRUE(fs::is_regular_file(prefix / "share/lidarscout/web/index.html"));  // the page of `serve`

    // Run from a folder outside both trees, with nothing pointing back at them.
    const std::string program = "cd " + prefix.string() + " && env -u LIDARSCOUT_MODEL -u LIDARSCOUT_TORCH_RUNNER " +
                                (prefix / "bin/lidarscout").string();
    ASSERT_EQ(test::run_command(program + " --version", out), 0) << out;
    EXPECT_EQ(out.rfind("lidarscout 0.", 0), 0u) << out;
    const std::string tile = (test::surveys_dir() / "ky-jmo335-eastern-kentucky/N117E379.laz").string();
    ASSERT_EQ(test::run_command(program + " info --json " + tile, out), 0) << out;
    EXPECT_EQ(nlohmann::json::parse(out).at(0).at("error"), nullptr);
    // Moving the build's copies away would prove more; instead the installed files must be
    // the ones found: the model and the plugin are looked up beside the program first.
    const fs::path png = prefix / "out.png";
    ASSERT_EQ(test::run_command(program + " render " + tile + " -o " + png.string() +
                                    " --size 320x180 --until heightmaps --heightmaps cnn --json 2>&1",
                                out),
              0)
        << out;
    EXPECT_TRUE(fs::is_regular_file(png));
    const auto j = nlohmann::json::parse(out.substr(out.find('{')));
    EXPECT_NE(j.dump().find((prefix / "share/lidarscout/models/heightmap_cnn.pt").string()), std::string::npos)
        << "the installed model was not the one used: " << j.dump();
    fs::remove_all(prefix);
}

}  // namespace
}  // namespace lidarscout
