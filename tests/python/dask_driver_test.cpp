// The Dask driver (python/lidarscout_dask, run by /usr/bin/python3 with Debian's python3-distributed
// and python3-gdal) on a LocalCluster of 2 workers: the dtm, chm and density of the classified
// Woodford tile made in 4 pieces and mosaicked equal the one-process `lidarscout dem` run, the
// decoded rasters byte for byte; a piece whose subprocess fails is retried; a rerun after a lost
// piece makes that piece only; the driver's output may not be an input.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>

#include "raster/gdal_test_util.hpp"
#include "temp_dir_fixture.hpp"
#include "test_data.hpp"

namespace lidarscout {
namespace {

namespace fs = std::filesystem;

class DaskDriver : public test::TempDirTest {
protected:
    static std::string woodford() { return (test::surveys_dir() / "ky-woodford-county").string(); }

    // `python3 -m lidarscout_dask dem WOODFORD -o OUT ARGS --local 2 --json`, its exit status; `out` its output.
    int drive(const std::string& output, const std::string& args, std::string& out) const {
        const fs::path python = fs::path(LIDARSCOUT_SOURCE_DIR) / "python";
        return test::run_command("cd " + python.string() + " && /usr/bin/python3 -m lidarscout_dask dem " + woodford() +
                                     " -o " + output + " " + args + " --local 2 --json 2>&1",
                                 out);
    }

    static void expect_same_raster(const std::string& a_path, const std::string& b_path) {
        const test::ReadRaster a = test::read_raster(a_path), b = test::read_raster(b_path);
        ASSERT_FALSE(a.values.empty()) << a_path;
        ASSERT_EQ(a.width, b.width);
        ASSERT_EQ(a.height, b.height);
        for (int i = 0; i < 6; ++i) EXPECT_EQ(a.transform[i], b.transform[i]) << i;
        EXPECT_EQ(a.nodata, b.nodata);
        EXPECT_EQ(a.epsg, b.epsg);
        ASSERT_EQ(a.values.size(), b.values.size());
        EXPECT_EQ(std::memcmp(a.values.data(), b.values.data(), a.values.size() * sizeof(float)), 0) << a_path;
    }

    static nlohmann::json last_json(const std::string& out) {
        const auto at = out.rfind("\n{");
        return nlohmann::json::parse(at == std::string::npos ? out : out.substr(at + 1));
    }
};

TEST_F(DaskDriver, PiecesOnALocalClusterEqualOneRun) {
    const std::string args = "--texel 1 --product dtm,chm,density";
    std::string out;
    ASSERT_EQ(test::run_command(std::string(LIDARSCOUT_CLI) + " dem " + woodford() + " -o " + path("one.tif") + " " +
                                    args + " --threads 2 2>&1",
                                out),
              0)
        << out;
    // The first try of one piece fails (the program refuses once): Dask retries it.
    const std::string flaky = path("flaky.sh");
    std::ofstream(flaky) << "#!/bin/sh\ncase \"$*\" in *--block*) if mkdir " << path("failed_once")
                         << " 2>/dev/null; then echo refused >&2; exit 3; fi;; esac\nexec " << LIDARSCOUT_CLI
                         << " \"$@\"\n";
    fs::permissions(flaky, fs::perms::owner_all);
    ASSERT_EQ(drive(path("four.tif"), args + " --pieces 4 --keep-pieces --program " + flaky, out), 0) << out;
    EXPECT_TRUE(fs::exists(path("failed_once")));
    nlohmann::json j = last_json(out);
    EXPECT_EQ(j.at("pieces"), 4);
    EXPECT_EQ(j.at("pieces_made"), 4);
    EXPECT_GT(j.at("peak_resident_bytes_max").get<double>(), 0);
    for (const char* name : {"dtm", "chm", "density"}) {
        expect_same_raster(path(("four_" + std::string(name) + ".tif").c_str()),
                           path(("one_" + std::string(name) + ".tif").c_str()));
    }
    // A worker died with piece 2 (its record lost): the rerun makes that piece only, the same mosaic.
    const fs::path pieces = dir / "four.tif.pieces";
    ASSERT_TRUE(fs::remove(pieces / "piece_00002_of_00004.json"));
    ASSERT_EQ(drive(path("four.tif"), args + " --pieces 4 --program " + std::string(LIDARSCOUT_CLI), out), 0) << out;
    j = last_json(out);
    EXPECT_EQ(j.at("pieces_made"), 1);
    EXPECT_EQ(j.at("pieces_skipped"), 3);
    EXPECT_FALSE(fs::exists(pieces));  // removed once mosaicked
    for (const char* name : {"dtm", "chm", "density"}) {
        expect_same_raster(path(("four_" + std::string(name) + ".tif").c_str()),
                           path(("one_" + std::string(name) + ".tif").c_str()));
    }
}

TEST_F(DaskDriver, RefusesAnInputAsOutputAndWholeRasterOptions) {
    std::string out;
    const std::string input = (test::surveys_dir() / "ky-woodford-county" / "5205000_3900000.laz").string();
    EXPECT_NE(drive(input, "--texel 4", out), 0);
    EXPECT_NE(out.find("the output must be a .tif"), std::string::npos) << out;
    EXPECT_NE(drive(path("h.tif"), "--texel 4 --hillshade " + path("h.png"), out), 0);
    EXPECT_NE(out.find("--hillshade does not apply"), std::string::npos) << out;
    EXPECT_FALSE(fs::exists(path("h.tif")));
}

}  // namespace
}  // namespace lidarscout
