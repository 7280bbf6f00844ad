// The viewer's exports without a window: an export is refused when it would replace an input or has
// the wrong extension; the area's clip written in the background is the file clip_to_file writes;
// a profile's CSV is write_profile_csv's and its LAZ the corridor clipped; an export closed while
// it runs leaves no file, not even a temporary one; a read told to stop says so.
#include "viewer/background_reads.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>

#include "core/error.hpp"
#include "core/thread_pool.hpp"
#include "pipelines/clip.hpp"
#include "temp_dir_fixture.hpp"
#include "test_data.hpp"

namespace lidarscout::viewer {
namespace {

std::string bytes_of(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

class ViewerExports : public test::TempDirTest {
protected:
    void SetUp() override {
        TempDirTest::SetUp();
        tile = (test::surveys_dir() / "ky-woodford-county" / "5205000_3900000.laz").string();
        ds = dataset::open_dataset({tile});
        ASSERT_EQ(ds.tiles.size(), 1u);
        const auto& h = ds.tiles[0].tile.header;
        const double x = h.min[0], y = h.min[1], w = h.max[0] - h.min[0], d = h.max[1] - h.min[1];
        square = pipelines::box_region(x + 0.4 * w, y + 0.4 * d, x + 0.5 * w, y + 0.5 * d);
        corridor = {x + 0.1 * w, y + 0.1 * d, x + 0.9 * w, y + 0.8 * d, 6.0};
    }
    // Waits for the task; its result line.
    static std::string finished(ExportTask& task) {
        while (!task.done()) std::this_thread::yield();
        EXPECT_FALSE(task.failed()) << task.status();
        return task.status();
    }
    std::string tile;
    dataset::Dataset ds;
    pipelines::Region square;
    pipelines::Corridor corridor;
};

TEST_F(ViewerExports, AnExportThatWouldReplaceAnInputIsRefused) {
    EXPECT_THROW(check_export(tile, io::OutputKind::PointCloud, {tile}), Error);
    EXPECT_THROW(check_export(path("a.txt"), io::OutputKind::PointCloud, {tile}), Error);
    EXPECT_THROW(check_export(path("none/a.laz"), io::OutputKind::PointCloud, {tile}), Error);
    EXPECT_THROW(check_export("", io::OutputKind::Profile, {tile}), Error);
    EXPECT_THROW(check_export(path("p.tif"), io::OutputKind::Profile, {tile}), Error);
    EXPECT_NO_THROW(check_export(path("a.laz"), io::OutputKind::PointCloud, {tile}));
    EXPECT_NO_THROW(check_export(path("p.csv"), io::OutputKind::Profile, {tile}));
    EXPECT_FALSE(std::filesystem::exists(path("a.laz")));  // checking creates nothing
}

TEST_F(ViewerExports, TheAreasClipIsWhatClipWrites) {
    const auto task = export_clip(ds, path("area.laz"), square, PointFilter::parse("2", "", ""), 2);
    const std::string line = finished(*task);
    const auto r = pipelines::clip_to_file(ds, {path("clip.laz"), square, PointFilter::parse("2", "", ""), {}},
                                           ThreadPool::shared());
    ASSERT_GT(r.points_written, 100u);
    EXPECT_EQ(line, "clip: " + std::to_string(r.points_written) + " points written to " + path("area.laz"));
    EXPECT_EQ(bytes_of(path("area.laz")), bytes_of(path("clip.laz")));
}

TEST_F(ViewerExports, AProfilesCsvAndLaz) {
    auto profile = std::make_shared<const pipelines::Profile>(
        pipelines::read_profile(ds, corridor, PointFilter(), ThreadPool::shared()));
    const auto csv = export_profile(ds, path("p.csv"), corridor, PointFilter(), profile, 2);
    EXPECT_EQ(finished(*csv), "profile: " + std::to_string(profile->points.size()) + " points written to " +
                                  path("p.csv"));
    pipelines::write_profile_csv(path("expected.csv"), ds, *profile);
    EXPECT_EQ(bytes_of(path("p.csv")), bytes_of(path("expected.csv")));
    const auto laz = export_profile(ds, path("p.laz"), corridor, PointFilter(), nullptr, 2);  // read again
    EXPECT_EQ(finished(*laz), "profile: " + std::to_string(profile->points.size()) + " points written to " +
                                  path("p.laz"));
    const auto png = export_profile(ds, path("p.png"), corridor, PointFilter(), profile, 2);
    finished(*png);
    EXPECT_GT(std::filesystem::file_size(path("p.png")), 1000u);
    EXPECT_THROW(export_profile(ds, path("q.csv"), corridor, PointFilter(), nullptr, 2), Error);  // not read yet
}

TEST_F(ViewerExports, ClosedWhileWritingItLeavesNoFile) {
    const auto whole = pipelines::box_region(-1e12, -1e12, 1e12, 1e12);
    const auto survey = dataset::open_dataset({(test::surveys_dir() / "ky-jmo335-eastern-kentucky").string()});
    ASSERT_GT(survey.tiles.size(), 2u);  // 15.7 M points: far more than is read before the cancel
    for (int k = 0; k < 2; ++k) {
        auto task = export_clip(survey, path("all.laz"), whole, PointFilter(), 2);
        if (k == 1) {
            task->cancel();
            while (!task->done()) std::this_thread::yield();
            EXPECT_TRUE(task->failed());
            EXPECT_NE(task->status().find("cancelled"), std::string::npos) << task->status();
        }
        task.reset();  // cancels and waits
        EXPECT_TRUE(std::filesystem::is_empty(dir)) << "a file was left";
    }
}

}  // namespace
}  // namespace lidarscout::viewer
