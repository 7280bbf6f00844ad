// The layering rule of cmake/stages.cmake, shown failing: a tiny project of two stages in which
// `b` includes a header of `a` without declaring it does not configure (the message names both
// stages and the file), nor does one that declares a stage it includes nothing of; declared
// properly, it configures (the control). And a stage with a FACADE: a later stage that includes
// one of its other headers does not compile, one that includes the facade does.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "temp_dir_fixture.hpp"
#include "test_data.hpp"

namespace lidarscout {
namespace {

namespace fs = std::filesystem;

class StageIncludes : public test::TempDirTest {
protected:
    // Writes the project with `b`'s stage line, configures it; returns the exit status, output in `out`.
    int configure(const std::string& b_stage, std::string& out, const std::string& a_stage = "lidarscout_stage(a)") {
        fs::create_directories(dir / "src/a");
        fs::create_directories(dir / "src/b");
        std::ofstream(dir / "src/a/x.hpp") << "#pragma once\ninline int x() { return 1; }\n";
        std::ofstream(dir / "src/a/x.cpp") << "#include \"a/x.hpp\"\nint y() { return x(); }\n";
        std::ofstream(dir / "src/b/z.cpp") << "#include \"a/x.hpp\"\nint z() { return x(); }\n";
        std::ofstream(dir / "CMakeLists.txt")
            << "cmake_minimum_required(VERSION 3.20)\nproject(stages CXX)\n"
            << "include(" << LIDARSCOUT_SOURCE_DIR << "/cmake/stages.cmake)\n"
            << a_stage << "\n" << b_stage << "\n";
        return test::run_command("cmake -S " + dir.string() + " -B " + (dir / "build").string() + " 2>&1", out);
    }
};

TEST_F(StageIncludes, AnUndeclaredIncludeFailsTheConfigureNamingBothStages) {
    std::string out;
    EXPECT_NE(configure("lidarscout_stage(b)", out), 0);
    EXPECT_NE(out.find("stage b includes stage a without declaring it (src/b/z.cpp"), std::string::npos) << out;
}

TEST_F(StageIncludes, AProperDeclarationConfiguresAnUnusedOneFails) {
    std::string out;
    ASSERT_EQ(configure("lidarscout_stage(b DEPS a)", out), 0) << out;  // the control
    std::ofstream(dir / "src/b/z.cpp") << "int z() { return 2; }\n";     // b no longer includes a
    EXPECT_NE(test::run_command("cmake " + (dir / "build").string() + " 2>&1", out), 0);
    EXPECT_NE(out.find("stage b declares DEPS a but includes nothing of them"), std::string::npos) << out;
}

TEST_F(StageIncludes, AHeaderBehindAFacadeDoesNotCompileInALaterStage) {
    std::string out;
    std::ofstream(dir / "src/a/hidden.hpp") << "#pragma once\ninline int hidden() { return 3; }\n";
    ASSERT_EQ(configure("lidarscout_stage(b DEPS a)", out, "lidarscout_stage(a FACADE x.hpp)"), 0) << out;
    const std::string build = "cmake --build " + (dir / "build").string() + " 2>&1";
    EXPECT_EQ(test::run_command(build, out), 0) << out;  // the control: b includes the facade
    std::ofstream(dir / "src/b/z.cpp") << "#include \"a/hidden.hpp\"\nint z() { return hidden(); }\n";
    EXPECT_NE(test::run_command(build, out), 0);
    EXPECT_NE(out.find("a/hidden.hpp"), std::string::npos) << out;
}

}  // namespace
}  // namespace lidarscout
