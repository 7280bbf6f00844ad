// io::check_outputs: an output never replaces an input (by device and inode, whatever the
// spelling or link), never adds a tile to an input folder, has its kind's extension and a
// writable folder; nothing is created when it is refused.
#include "io/output_check.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "core/error.hpp"
#include "io/output_file.hpp"
#include "temp_dir_fixture.hpp"

namespace lidarscout::io {
namespace {

namespace fs = std::filesystem;

class OutputCheck : public test::TempDirTest {
protected:
    void SetUp() override {
        TempDirTest::SetUp();
        fs::create_directories(dir / "survey");
        tile = path("survey/t.laz");
        std::ofstream(tile) << "LASF and more";
    }
    void TearDown() override {
        forget_protected_inputs();
        TempDirTest::TearDown();
    }
    // The message of the Error check_outputs throws, or "" when it accepts.
    static std::string refusal(const std::vector<OutputTarget>& outputs, const std::vector<std::string>& inputs) {
        try {
            check_outputs(outputs, inputs);
        } catch (const Error& e) {
            return e.what();
        }
        return {};
    }
    std::size_t entries() const {
        return static_cast<std::size_t>(std::distance(fs::directory_iterator(dir), fs::directory_iterator()));
    }
    std::string tile;
};

TEST_F(OutputCheck, TheSameFileHoweverSpelledIsRefusedNamingBoth) {
    const auto cwd = fs::current_path();
    fs::current_path(dir);
    const std::string dot = refusal({{"./survey/t.laz", "-o", OutputKind::GeoTiff}}, {"survey/t.laz"});
    fs::current_path(cwd);
    EXPECT_NE(dot.find("./survey/t.laz"), std::string::npos) << dot;
    EXPECT_NE(dot.find("it is the input survey/t.laz (the same file)"), std::string::npos) << dot;
    const std::string absolute = refusal({{fs::absolute(tile).string(), "-o", OutputKind::GeoTiff}}, {tile});
    EXPECT_NE(absolute.find("refusing the output of -o: it is the input " + tile), std::string::npos) << absolute;
}

TEST_F(OutputCheck, SymbolicAndHardLinksAreTheSameFile) {
    fs::create_symlink(tile, path("soft.tif"));
    fs::create_hard_link(tile, path("hard.laz"));
    EXPECT_NE(refusal({{path("soft.tif"), "--rgb", OutputKind::GeoTiff}}, {tile}).find("it is the input"),
              std::string::npos);
    EXPECT_NE(refusal({{path("hard.laz"), "-o", OutputKind::PointCloud}}, {tile}).find("it is the input"),
              std::string::npos);
    // the link named as the input, the file itself as the output
    EXPECT_NE(refusal({{tile, "-o", OutputKind::PointCloud}}, {path("soft.tif")}).find("it is the input"),
              std::string::npos);
    // a different file of the same name elsewhere is fine (the control)
    EXPECT_EQ(refusal({{path("other.laz"), "-o", OutputKind::PointCloud}}, {tile}), "");
}

TEST_F(OutputCheck, ATileNameInsideAnInputFolderIsRefusedOtherNamesAreNot) {
    const std::string msg = refusal({{path("survey/sub/new.laz"), "-o", OutputKind::PointCloud}}, {path("survey")});
    // (the folder "sub" does not exist either, but the input folder is named first)
    EXPECT_NE(msg.find("inside the input folder " + path("survey") + " with a tile's name"), std::string::npos) << msg;
    EXPECT_EQ(refusal({{path("survey/dem.tif"), "-o", OutputKind::GeoTiff}}, {path("survey")}), "");
    EXPECT_NE(refusal({{path("survey/copy"), "-o", OutputKind::Folder}}, {path("survey")}).find("input folder"),
              std::string::npos);
    EXPECT_NE(refusal({{path("survey"), "-o", OutputKind::Folder}}, {path("survey")}).find("the same folder"),
              std::string::npos);
}

TEST_F(OutputCheck, TheExtensionMustMatchWhatIsWritten) {
    const std::string laz = refusal({{path("x.laz"), "-o", OutputKind::GeoTiff}}, {tile});
    EXPECT_NE(laz.find("it must end in one of .tif, .tiff (.laz given)"), std::string::npos) << laz;
    const std::string tif = refusal({{path("x.tif"), "-o", OutputKind::Png}}, {tile});
    EXPECT_NE(tif.find("it must end in .png (.tif given)"), std::string::npos) << tif;
    EXPECT_NE(refusal({{path("x.laz"), "-o", OutputKind::TrainingData}}, {tile}).find("not a .laz file"),
              std::string::npos);
    EXPECT_EQ(refusal({{path("x.TIFF"), "-o", OutputKind::GeoTiff}, {path("h.png"), "--hillshade",
                                                                     OutputKind::Hillshade}}, {tile}), "");
    EXPECT_EQ(refusal({{path("train.bin"), "-o", OutputKind::TrainingData}}, {tile}), "");
}

TEST_F(OutputCheck, AMissingUnwritableOrFileFolderIsRefusedAndNothingIsCreated) {
    const std::size_t before = entries();
    EXPECT_NE(refusal({{path("nowhere/x.tif"), "-o", OutputKind::GeoTiff}}, {tile}).find("does not exist"),
              std::string::npos);
    EXPECT_NE(refusal({{tile + "/x.tif", "-o", OutputKind::GeoTiff}}, {}).find("is a file, not a folder"),
              std::string::npos);
    // /proc/self takes no new files, whoever runs the test (root included)
    EXPECT_NE(refusal({{"/proc/self/x.tif", "-o", OutputKind::GeoTiff}}, {}).find("is not writable"),
              std::string::npos);
    EXPECT_NE(refusal({{path("survey"), "-o", OutputKind::GeoTiff}}, {}).find("it is a folder"), std::string::npos);
    EXPECT_NE(refusal({{tile, "-o", OutputKind::Folder}}, {}).find("it is a file, not a folder"), std::string::npos);
    EXPECT_EQ(refusal({{path("new/deeper"), "-o", OutputKind::Folder}}, {}), "");  // created later, by the writer
    EXPECT_EQ(entries(), before);
}

TEST_F(OutputCheck, TwoOutputsOfOneCommandNeedTwoNames) {
    const std::string msg = refusal({{path("o.tif"), "-o", OutputKind::GeoTiff},
                                     {path("./o.tif"), "--rgb", OutputKind::GeoTiff}}, {tile});
    EXPECT_NE(msg.find("refusing the output of --rgb: it is also the output of -o"), std::string::npos) << msg;
}

TEST_F(OutputCheck, AWriterThatSkippedTheCheckStillCannotReplaceAnInput) {
    fs::create_hard_link(tile, path("alias.bin"));
    protect_inputs({tile});
    EXPECT_THROW(AtomicOutputFile out(path("alias.bin")), Error);
    AtomicOutputFile fine(path("fine.bin"));  // the control: other files are written
    fine.commit();
    EXPECT_TRUE(fs::exists(path("fine.bin")));
    std::ifstream in(tile);
    std::string text;
    std::getline(in, text);
    EXPECT_EQ(text, "LASF and more");
}

}  // namespace
}  // namespace lidarscout::io
