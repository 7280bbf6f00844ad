// `lidarscout dem --product dtm,dsm,chm --hillshade --contours` is all or nothing: a real run on the
// Woodford tile, a child process, is sent SIGINT at several points (while the points are gridded,
// while each product's COG, the hillshade and the contours are written: seen by their temporary files
// appearing in the folder) and once left to finish. Each time either every output is new and complete
// (read back by GDAL) or none is: the files that were there before are untouched, byte for byte; and
// no temporary or scratch file is left.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <thread>

#include "raster/gdal_test_util.hpp"
#include "temp_dir_fixture.hpp"
#include "test_data.hpp"

namespace lidarscout {
namespace {

namespace fs = std::filesystem;

const char* const kOutputs[] = {"d_dtm.tif", "d_dsm.tif", "d_chm.tif", "d.png", "d.pgw", "d.png.aux.xml",
                                "d_dtm_contours.gpkg"};
constexpr const char* kOld = "a file that was there before the run\n";

class DemInterrupt : public test::TempDirTest {
protected:
    // The names in the folder.
    std::vector<std::string> names() const {
        std::vector<std::string> out;
        std::error_code ec;
        for (auto it = fs::directory_iterator(dir, ec); !ec && it != fs::directory_iterator(); it.increment(ec)) {
            out.push_back(it->path().filename().string());
        }
        return out;
    }

    bool has_name_starting(const std::string& start) const {
        for (const auto& n : names()) {
            if (n.rfind(start, 0) == 0) return true;
        }
        return false;
    }

    // Runs the dem, sends SIGINT once `ready()` holds (never when it is null); true when the signal ended it,
    // false when it exited 0 first.
    bool run_dem(const std::function<bool()>& ready) const {
        const std::string woodford = (test::surveys_dir() / "ky-woodford-county").string();
        const std::string out = path("d.tif"), shade = path("d.png"), err = path("err.txt");
        const pid_t pid = ::fork();
        if (pid == 0) {
            const int fd = ::open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
            ::dup2(fd, 2);
            ::dup2(fd, 1);
            ::execl(LIDARSCOUT_CLI, LIDARSCOUT_CLI, "dem", woodford.c_str(), "-o", out.c_str(), "--texel", "1",
                    "--product", "dtm,dsm,chm", "--hillshade", shade.c_str(), "--contours", "2", "--threads", "2",
                    static_cast<char*>(nullptr));
            ::_exit(127);
        }
        int status = 0;
        bool sent = false;
        while (::waitpid(pid, &status, WNOHANG) == 0) {
            if (!sent && ready && ready()) {
                ::kill(pid, SIGINT);
                sent = true;
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(1));
        }
        std::ifstream in(err);
        const std::string said((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        fs::remove(err);
        if (WIFSIGNALED(status)) {
            EXPECT_EQ(WTERMSIG(status), SIGINT);
            return true;
        }
        EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << status << ": " << said;
        return false;
    }

    void write_old_outputs() const {
        for (const char* name : kOutputs) std::ofstream(path(name)) << kOld;
    }

    // How many outputs are the old files (byte for byte), and how many are new; no other file is there.
    std::pair<int, int> old_and_new() const {
        int old = 0, made = 0;
        for (const char* name : kOutputs) {
            if (!fs::exists(path(name))) continue;
            std::ifstream in(path(name));
            const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
            ++(bytes == kOld ? old : made);
        }
        EXPECT_EQ(names().size(), static_cast<std::size_t>(old + made)) << "temporary files left: " << listing();
        return {old, made};
    }

    std::string listing() const {
        std::string s;
        for (const auto& n : names()) s += n + " ";
        return s;
    }

    void expect_complete_set() const {
        for (const char* name : {"d_dtm.tif", "d_dsm.tif", "d_chm.tif"}) {
            const auto r = test::read_raster(path(name));
            EXPECT_GT(r.width, 100) << name;
            EXPECT_EQ(r.values.size(), static_cast<std::size_t>(r.width) * r.height) << name;
        }
        const auto shade = test::gdalinfo(path("d.png"));
        EXPECT_TRUE(shade.contains("coordinateSystem")) << "the PNG's .aux.xml";
        std::string out;
        ASSERT_EQ(test::run_command("ogrinfo -so -al " + path("d_dtm_contours.gpkg") + " 2>&1", out), 0) << out;
        EXPECT_NE(out.find("Feature Count: "), std::string::npos) << out;
        EXPECT_EQ(out.find("Feature Count: 0\n"), std::string::npos) << out;
    }
};

TEST_F(DemInterrupt, AnInterruptedProductSetLeavesTheEarlierFilesAndNoneOfTheNew) {
    const std::string pid_part = ".tmp-";
    // Where the run is when the signal goes: the temporary file (or scratch raster) that has appeared.
    const std::vector<std::pair<std::string, std::string>> points = {
        {"gridding", ".d_dtm.tif.blocks-"},   {"dtm COG", ".d_dtm.tif" + pid_part},
        {"dsm COG", ".d_dsm.tif" + pid_part}, {"chm COG", ".d_chm.tif" + pid_part},
        {"hillshade", ".d.png" + pid_part},   {"contours", ".d_dtm_contours.gpkg" + pid_part}};
    int interrupted = 0;
    for (std::size_t i = 0; i < points.size(); ++i) {
        SCOPED_TRACE(points[i].first);
        const bool before = i % 2 == 1;  // every other run replaces files that were there
        if (before) write_old_outputs();
        const std::string start = points[i].second;
        const bool signalled = run_dem([&] { return has_name_starting(start); });
        const auto [old, made] = old_and_new();
        if (made == 0) {  // none of the new files, every old one as it was
            EXPECT_TRUE(signalled);
            EXPECT_EQ(old, before ? 7 : 0) << listing();
            ++interrupted;
        } else {  // the signal came during the last renames (held until they were done), or after the end
            EXPECT_EQ(made, 7) << listing();
            EXPECT_EQ(old, 0) << listing();
            expect_complete_set();
        }
        for (const char* name : kOutputs) fs::remove(path(name));
    }
    EXPECT_GE(interrupted, 5) << "the signal came too late to test anything";
    write_old_outputs();  // uninterrupted, over the old files: every one replaced
    EXPECT_FALSE(run_dem(nullptr));
    EXPECT_EQ(old_and_new(), std::make_pair(0, 7)) << listing();
    expect_complete_set();
}

}  // namespace
}  // namespace lidarscout
