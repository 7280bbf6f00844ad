// The Dask driver (python/lidarscout_dask, run by /usr/bin/python3 with Debian's python3-distributed
// and python3-gdal, and this build's Python module) on a LocalCluster of 2 workers: the dtm, chm and
// density of the classified Woodford tile made in 4 pieces and mosaicked equal the one-process
// `lidarscout dem` run, the decoded rasters byte for byte; a piece whose dem_block fails (a lidarscout.Error
// raised by a sitecustomize.py the test puts first on the workers' PYTHONPATH) is retried; a rerun after a
// lost piece makes that piece only; the driver's output may not be an input. Its failures are one line
// "lidarscout_dask: ..." with exit status 1 and the JSON error with --json, never a traceback, and
// leave nothing behind (no output, no pieces folder) but the finished pieces of a run a rerun can use.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "raster/gdal_test_util.hpp"
#include "temp_dir_fixture.hpp"
#include "test_data.hpp"

namespace lidarscout {
namespace {

namespace fs = std::filesystem;

class DaskDriver : public test::TempDirTest {
protected:
    static std::string woodford() { return (test::surveys_dir() / "ky-woodford-county").string(); }

    // PYTHONPATH: the hook folder (when `hook` is set), and this build's module and driver (build/python), or
    // without `module` the sources' (python/: the driver, and the module's Python side without its library).
    std::string python_path(bool module = true) const {
        const fs::path python = module ? fs::path(LIDARSCOUT_BUILD_DIR) : fs::path(LIDARSCOUT_SOURCE_DIR);
        return "cd " + dir.string() + " && PYTHONPATH=" + (hook.empty() ? "" : path("hook") + ":") +
               (python / "python").string() + " ";
    }

    // Every piece's ds.dem_block raises lidarscout.Error("refused") when the Python expression `when`
    // (of `index`, `count`, once(FOLDER): true the first time only) holds: a sitecustomize.py that every
    // process of the driver imports first.
    void fail_pieces_when(const std::string& when) {
        hook = when;
        fs::create_directories(path("hook"));
        std::ofstream(path("hook/sitecustomize.py"))
            << "import os\nimport lidarscout\nREAL = lidarscout.Dataset.dem_block\n\n\n"
               "def once(folder):\n    try:\n        os.mkdir(folder)\n        return True\n"
               "    except FileExistsError:\n        return False\n\n\n"
               "def dem_block(self, index, count, output, **options):\n"
               "    if " << when << ":\n"
               "        raise lidarscout.Error('refused', None, None, 'refused')\n"
               "    return REAL(self, index, count, output, **options)\n\n\n"
               "lidarscout.Dataset.dem_block = dem_block\n";
    }

    // `python3 -m lidarscout_dask dem WOODFORD -o OUT ARGS --local 2 --json`, its exit status; `out` its output.
    int drive(const std::string& output, const std::string& args, std::string& out) const {
        return test::run_command(python_path() + "/usr/bin/python3 -m lidarscout_dask dem " + woodford() + " -o " +
                                     output + " " + args + " --local 2 --json 2>&1",
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

    struct Run {
        int status = 0;
        std::string out, err;
    };
    // `python3 -m lidarscout_dask ARGS --json`, its stdout and stderr apart.
    Run driver(const std::string& args, bool module = true) const {
        Run r;
        r.status = test::run_command(python_path(module) + "/usr/bin/python3 -m lidarscout_dask " + args +
                                         " --json 2>" + path("err.txt"), r.out);
        std::ifstream in(path("err.txt"));
        r.err.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
        fs::remove(path("err.txt"));
        return r;
    }

    // Exit status 1, the last stderr line "lidarscout_dask: " + a message holding `expected`, the same
    // message in the JSON error of kind `kind`, no traceback; returns the message.
    static std::string expect_failure(const Run& r, const std::string& expected, const std::string& kind) {
        EXPECT_EQ(r.status, 1) << r.err;
        EXPECT_EQ(r.err.find("Traceback"), std::string::npos) << r.err;
        const std::string err = r.err.substr(0, r.err.find_last_not_of('\n') + 1);
        const std::string line = err.substr(err.rfind('\n') == std::string::npos ? 0 : err.rfind('\n') + 1);
        EXPECT_EQ(line.rfind("lidarscout_dask: ", 0), 0u) << r.err;
        EXPECT_NE(line.find(expected), std::string::npos) << r.err;
        const auto j = nlohmann::json::parse(r.out, nullptr, false);
        EXPECT_FALSE(j.is_discarded()) << r.out;
        if (j.is_discarded()) return {};
        EXPECT_EQ(j.at("error").at("kind"), kind) << r.out;
        EXPECT_EQ("lidarscout_dask: " + j.at("error").at("message").get<std::string>(), line);
        for (const char* key : {"file", "offset", "cause"}) EXPECT_TRUE(j.at("error").contains(key)) << key;
        return line;
    }

    // Nothing in the folder but `kept`.
    void expect_only(const std::vector<std::string>& kept) const {
        for (const auto& e : fs::directory_iterator(dir)) {
            const std::string name = e.path().filename().string();
            EXPECT_NE(std::find(kept.begin(), kept.end(), name), kept.end()) << name << " left behind";
        }
    }

    static nlohmann::json last_json(const std::string& out) {
        const auto at = out.rfind("\n{");
        return nlohmann::json::parse(at == std::string::npos ? out : out.substr(at + 1));
    }

    std::string hook;  // fail_pieces_when's condition; empty: none
};

TEST_F(DaskDriver, PiecesOnALocalClusterEqualOneRun) {
    const std::string args = "--texel 1 --product dtm,chm,density";
    std::string out;
    ASSERT_EQ(test::run_command(std::string(LIDARSCOUT_CLI) + " dem " + woodford() + " -o " + path("one.tif") + " " +
                                    args + " --threads 2 2>&1",
                                out),
              0)
        << out;
    // The first try of one piece fails (dem_block raises lidarscout.Error once): Dask retries it.
    fail_pieces_when("once('" + path("failed_once") + "')");
    ASSERT_EQ(drive(path("four.tif"), args + " --pieces 4 --keep-pieces", out), 0) << out;
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
    hook.clear();
    ASSERT_EQ(drive(path("four.tif"), args + " --pieces 4", out), 0) << out;
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

// Before the cluster starts: a missing module, a missing input, a misspelt option (the driver's or
// dem's), a missing one, a value dem refuses, a bad --memory, a misspelt command. Nothing is made.
TEST_F(DaskDriver, FailuresBeforeAnyWorkAreOneLineAndLeaveNothing) {
    const std::string dem = "dem " + woodford() + " -o " + path("x.tif") + " --texel 4 ";
    expect_failure(driver(dem + "--local 2", false), "cannot import the lidarscout module", "input");
    expect_failure(driver("dem /nonexistent/a.laz -o " + path("x.tif") + " --local 2"),
                   "/nonexistent/a.laz: no such file or folder", "input");
    expect_failure(driver(dem + "--local 2 --textel 4"), "dem: unknown option '--textel' (did you mean '--texel'?)",
                   "usage");  // dem's
    expect_failure(driver(dem + "--local 2 --pices 4"),
                   "dem: unknown option '--pices' (did you mean '--pieces'?)", "usage");  // the driver's own
    expect_failure(driver(dem + "--locl 2"), "dem: unknown option '--locl' (did you mean '--local'?)", "usage");
    expect_failure(driver(dem), "dem: one of the arguments --scheduler --local is required", "usage");
    expect_failure(driver(dem + "--local 2 --radius 0"), "dem: --radius: must be more than 0, not '0'",
                   "usage");  // the module's check, as `lidarscout dem` says it
    expect_failure(driver(dem + "--local 2 --product dtm --method idw"), "dem: --method does not apply to --product",
                   "usage");
    expect_failure(driver(dem + "--local 2 --memory lots"), "dem: bad --memory 'lots'", "usage");
    expect_failure(driver("dme " + woodford()), "unknown command 'dme' (did you mean 'dem'?)", "usage");
    const Run r = driver(dem + "--local 2", false);
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    expect_only({});
}

// A piece that fails every try: the others go on; with no finished piece the pieces folder goes too,
// with finished ones they are kept for the rerun, and the error says where. A piece over its --memory
// is refused before any work, on the worker, and reported the same way.
TEST_F(DaskDriver, AFailedPieceLeavesOnlyTheFinishedPieces) {
    fail_pieces_when("index == 2");
    const std::string dem = "dem " + woodford() + " -o " + path("x.tif") + " --texel 1 --local 2 --pieces 4 "
                            "--retries 0";
    std::string line = expect_failure(driver(dem), "piece 2/4 on ", "input");
    EXPECT_NE(line.find("refused"), std::string::npos) << line;
    EXPECT_NE(line.find("finished pieces kept in " + path("x.tif.pieces")), std::string::npos) << line;
    std::size_t records = 0;
    for (const auto& e : fs::directory_iterator(dir / "x.tif.pieces")) records += e.path().extension() == ".json";
    EXPECT_EQ(records, 4u);  // run.json and the three finished pieces' records: the others went on
    fs::remove_all(dir / "x.tif.pieces");
    fail_pieces_when("True");
    line = expect_failure(driver(dem), ": refused (and 3 more pieces failed)", "input");
    EXPECT_EQ(line.find("kept"), std::string::npos) << line;
    expect_only({"hook"});
    hook.clear();
    line = expect_failure(driver(dem + " --memory 1M"), "memory", "input");
    EXPECT_NE(line.find("piece "), std::string::npos) << line;
    EXPECT_NE(line.find("(and 3 more pieces failed)"), std::string::npos) << line;
    expect_only({"hook"});
}

}  // namespace
}  // namespace lidarscout
