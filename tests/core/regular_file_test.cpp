// core/regular_file: a FIFO, a folder and a device are refused by name and kind before any read,
// a regular file passes (its descriptor blocking again), a missing one is left to the open; and
// every reader of a local input (io::File, batch read targets, polygons, sessions, virtual replica
// manifests, catalogs, tile lists) refuses a FIFO in one line. A read of a FIFO without a writer
// would wait forever: this test ends because nothing opens one to read it.
#include "core/regular_file.hpp"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <fstream>
#include <functional>

#include "core/error.hpp"
#include "core/polygon.hpp"
#include "dataset/file_search.hpp"
#include "dataset/stac_catalog.hpp"
#include "dataset/virtual_replica.hpp"
#include "io/batch_reader.hpp"
#include "io/file.hpp"
#include "temp_dir_fixture.hpp"
#include "viewer/session_file.hpp"

namespace lidarscout {
namespace {

class RegularFile : public test::TempDirTest {
protected:
    std::string fifo(const char* name) {
        EXPECT_EQ(::mkfifo(path(name).c_str(), 0600), 0) << name;
        return path(name);
    }
};

// The cause of the Error `read` throws, "" when it throws none.
std::string refusal(const std::function<void()>& read) {
    try {
        read();
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

TEST_F(RegularFile, WhatIsNotARegularFileIsRefusedByKind) {
    const std::string pipe = fifo("pipe");
    EXPECT_EQ(refusal([&] { require_regular_file(pipe); }),
              pipe + ": is a FIFO (named pipe), not a regular file: not read");
    EXPECT_NE(refusal([&] { require_regular_file(dir.string()); }).find("is a folder, not a regular file"),
              std::string::npos);
    EXPECT_NE(refusal([] { require_regular_file("/dev/null"); }).find("is a character device"), std::string::npos);
    std::ofstream(dir / "file") << "x";
    EXPECT_EQ(refusal([&] { require_regular_file(path("file")); }), "");
    EXPECT_EQ(refusal([&] { require_regular_file(path("missing")); }), "") << "left to the open, which names why";
    EXPECT_EQ(non_regular_kind(S_IFSOCK), "a socket");
    EXPECT_EQ(non_regular_kind(S_IFREG), "");
}

TEST_F(RegularFile, AnOpenNeverBlocksOnAFifoAndLeavesARegularFileBlocking) {
    const std::string pipe = fifo("pipe");
    EXPECT_NE(refusal([&] { open_regular_file(pipe); }).find("is a FIFO"), std::string::npos);
    std::ofstream(dir / "file") << "x";
    const int fd = open_regular_file(path("file"));
    ASSERT_GE(fd, 0);
    const int flags = ::fcntl(fd, F_GETFL);
    EXPECT_EQ(flags & O_NONBLOCK, 0);
    EXPECT_EQ(flags & O_ACCMODE, O_RDONLY);
    EXPECT_NE(::fcntl(fd, F_GETFD) & FD_CLOEXEC, 0);
    ::close(fd);
    errno = 0;
    EXPECT_EQ(open_regular_file(path("missing")), -1);
    EXPECT_EQ(errno, ENOENT);
}

TEST_F(RegularFile, EveryReaderOfALocalInputRefusesAFifoInOneLine) {
    const std::vector<std::pair<std::string, std::function<void(const std::string&)>>> readers = {
        {"tile.laz", [](const std::string& p) { io::File::open(p); }},
        {"batch.laz", [](const std::string& p) { io::ReadTarget::open(p, false); }},
        {"direct.laz", [](const std::string& p) { io::ReadTarget::open(p, true); }},
        {"area.geojson", [](const std::string& p) { read_polygon_argument(p); }},
        {"view.lidarscout.json", [](const std::string& p) { viewer::read_session(p); }},
        {"replicate.json", [](const std::string& p) { dataset::read_virtual_replica(p); }},
        {"catalog.json",
         [](const std::string& p) {
             const auto c = dataset::read_catalog(p);
             if (!c.errors.empty()) throw Error(c.errors.front());
         }},
    };
    for (const auto& [name, read] : readers) {
        const std::string pipe = fifo(name.c_str());
        const std::string line = refusal([&] { read(pipe); });
        EXPECT_NE(line.find(pipe + ": is a FIFO (named pipe), not a regular file"), std::string::npos) << name << line;
        EXPECT_EQ(line.find('\n'), std::string::npos) << line;
    }
    EXPECT_FALSE(dataset::is_tile_list(fifo("list.txt")));
    EXPECT_FALSE(dataset::is_virtual_replica(path("replicate.json")));
}

}  // namespace
}  // namespace lidarscout
