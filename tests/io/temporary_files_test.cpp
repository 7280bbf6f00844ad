// Temporary files and signals: a child process writing an output is ended by SIGINT or SIGTERM
// while the output is half written; the temporary file is gone, the target never appears, and
// the child ends by the signal (the default action still runs). A released guard leaves the
// file alone.
#include "io/temporary_files.hpp"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <vector>

#include "io/output_file.hpp"
#include "temp_dir_fixture.hpp"

namespace lidarscout::io {
namespace {

namespace fs = std::filesystem;

class TemporaryFiles : public test::TempDirTest {};

// Files in the folder whose name starts with a dot (the temporary files).
std::vector<fs::path> hidden_files(const fs::path& dir) {
    std::vector<fs::path> out;
    for (const auto& e : fs::directory_iterator(dir)) {
        if (e.path().filename().string().rfind('.', 0) == 0) out.push_back(e.path());
    }
    return out;
}

TEST_F(TemporaryFiles, AnInterruptedOutputLeavesNothingBehind) {
    for (const int sig : {SIGINT, SIGTERM}) {
        int ready[2];
        ASSERT_EQ(::pipe(ready), 0);
        const pid_t child = ::fork();
        ASSERT_GE(child, 0);
        if (child == 0) {
            remove_temporary_files_on_signal();
            AtomicOutputFile out(path("out.laz"));
            const std::vector<std::uint8_t> bytes(4096, 7);
            out.write(bytes);
            (void)!::write(ready[1], "x", 1);
            ::pause();  // the signal ends us here, before commit()
            ::_exit(0);
        }
        char c = 0;
        ASSERT_EQ(::read(ready[0], &c, 1), 1);
        ::close(ready[0]), ::close(ready[1]);
        EXPECT_EQ(hidden_files(dir).size(), 1u);  // the temporary file, half written
        ::kill(child, sig);
        int status = 0;
        ASSERT_EQ(::waitpid(child, &status, 0), child);
        EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == sig) << status;
        EXPECT_TRUE(hidden_files(dir).empty()) << "signal " << sig;
        EXPECT_FALSE(fs::exists(path("out.laz")));
    }
}

TEST_F(TemporaryFiles, AReleasedGuardLeavesItsFileAlone) {
    const std::string kept = path(".kept");
    std::ofstream(kept) << "data";
    { TemporaryFileGuard guard(kept); }
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
        remove_temporary_files_on_signal();
        ::raise(SIGTERM);
        ::_exit(0);
    }
    int status = 0;
    ASSERT_EQ(::waitpid(child, &status, 0), child);
    EXPECT_TRUE(WIFSIGNALED(status));
    EXPECT_TRUE(fs::exists(kept));
}

}  // namespace
}  // namespace lidarscout::io
