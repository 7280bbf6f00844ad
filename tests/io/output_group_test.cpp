// Output sets: files handed to an OutputGroup stay under their temporary names (the targets as they
// were) until commit() renames them all; a group dropped without commit() removes them. A signal
// that arrives during a SignalHold (in this thread or another) neither ends the process nor removes
// anything until the hold ends, and then does both.
#include "io/output_group.hpp"

#include <gtest/gtest.h>
#include <pthread.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <cstdint>
#include <span>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <thread>

#include "core/error.hpp"
#include "io/output_check.hpp"
#include "io/output_file.hpp"
#include "io/temporary_files.hpp"
#include "temp_dir_fixture.hpp"

namespace lidarscout::io {
namespace {

namespace fs = std::filesystem;

class OutputGroups : public test::TempDirTest {
protected:
    std::string read(const char* name) const {
        std::ifstream in(path(name));
        return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    }
    // `text` to `name` through an AtomicOutputFile handed to `group`.
    void write(const char* name, const std::string& text, OutputGroup& group) const {
        AtomicOutputFile out(path(name));
        out.write(std::span(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()));
        out.commit(group);
    }
    std::size_t files() const {
        return static_cast<std::size_t>(std::distance(fs::directory_iterator(dir), fs::directory_iterator()));
    }
};

TEST_F(OutputGroups, TheTargetsChangeOnlyWhenTheGroupCommits) {
    std::ofstream(path("a.tif")) << "old";
    {
        OutputGroup group;
        write("a.tif", "new a", group);
        write("b.tif", "new b", group);
        EXPECT_EQ(read("a.tif"), "old");
        EXPECT_FALSE(fs::exists(path("b.tif")));
        EXPECT_NE(group.path_of(path("a.tif")), path("a.tif"));  // where a writer of the set reads it
        EXPECT_EQ(std::ifstream(group.path_of(path("b.tif"))).get(), 'n');
        EXPECT_EQ(group.path_of(path("c.tif")), path("c.tif"));
        EXPECT_EQ(files(), 3u);  // a.tif and the two temporary files
        group.commit();
    }
    EXPECT_EQ(read("a.tif"), "new a");
    EXPECT_EQ(read("b.tif"), "new b");
    EXPECT_EQ(files(), 2u);
}

TEST_F(OutputGroups, AGroupDroppedWithoutCommitLeavesTheTargetsAsTheyWere) {
    std::ofstream(path("a.tif")) << "old";
    try {
        OutputGroup group;
        write("a.tif", "new a", group);
        write("b.tif", "new b", group);
        throw Error("a later output failed");
    } catch (const Error&) {
    }
    EXPECT_EQ(read("a.tif"), "old");
    EXPECT_EQ(files(), 1u);
}

TEST_F(OutputGroups, AProtectedInputCannotJoinAGroup) {
    std::ofstream(path("in.laz")) << "input";
    protect_inputs({path("in.laz")});
    OutputGroup group;
    EXPECT_THROW(group.add(path(".x.tmp"), path("in.laz")), Error);
    forget_protected_inputs();
    group.add(path(".b.tmp"), path("b.tif"));
    EXPECT_THROW(group.add(path(".c.tmp"), path("b.tif")), Error) << "one target, twice";
}

// In a child: a set of two files held, SIGINT raised in the hold by this thread and by another; the
// child goes on (it writes "alive") until the hold ends, then the signal ends it and removes the set.
TEST_F(OutputGroups, ASignalDuringAHoldWaitsForItsEnd) {
    for (const bool other_thread : {false, true}) {
        SCOPED_TRACE(other_thread ? "another thread" : "this thread");
        const pid_t child = ::fork();
        ASSERT_GE(child, 0);
        if (child == 0) {
            remove_temporary_files_on_signal();
            OutputGroup group;
            write("a.tif", "a", group);
            write("b.tif", "b", group);
            {
                const SignalHold hold;
                if (other_thread) {  // the handler runs in that thread, while this one holds
                    std::thread([] { ::pthread_kill(::pthread_self(), SIGINT); }).join();
                } else {
                    std::raise(SIGINT);
                }
                std::ofstream(path("alive")) << "the signal waited";
            }
            ::_exit(0);  // not reached: the held signal ends the process
        }
        int status = 0;
        ASSERT_EQ(::waitpid(child, &status, 0), child);
        EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGINT) << status;
        EXPECT_TRUE(fs::exists(path("alive")));
        EXPECT_EQ(files(), 1u) << "the set's temporary files removed, no target made";
        fs::remove(path("alive"));
    }
}

}  // namespace
}  // namespace lidarscout::io
