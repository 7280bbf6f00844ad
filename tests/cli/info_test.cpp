// `lidarscout info`: JSON output for the surveys equals the headers, Kentucky tiles report US
// survey feet, a bad file is one line on stderr and exit status 1 while the others are reported;
// remote files (HTTP, and HTTPS/HTTP2 with a private CA) give the local files' output; no
// secret of a URL is printed; damaged range cache entries do not change the output; a hostile
// --threads is capped with one warning; a compound CRS whose vertical part PROJ lacks gets
// lon/lat from its horizontal part; paths without tiles are named.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "child_process.hpp"
#include "core/thread_pool.hpp"
#include "dataset/file_search.hpp"
#include "io/file.hpp"
#include "las/header.hpp"
#include "nginx_server.hpp"
#include "test_data.hpp"

namespace lidarscout {
namespace {

nlohmann::json info_json(const std::string& args, int& status) {
    std::string out;
    status = test::run_command(std::string(LIDARSCOUT_CLI) + " info --json " + args + " 2>/dev/null", out);
    return nlohmann::json::parse(out);
}

TEST(InfoCommand, SurveysMatchHeaders) {
    int status = -1;
    auto files = info_json(test::surveys_dir().string(), status);
    EXPECT_EQ(status, 0);
    auto expected = dataset::find_point_cloud_files({test::surveys_dir().string()}).files;
    ASSERT_EQ(files.size(), expected.size());
    ASSERT_GT(files.size(), 100u);  // 9 + 1 + 1 + 8 + 7 + 4 + 77 tiles
    for (const auto& f : files) {
        const auto path = f.at("path").get<std::string>();
        SCOPED_TRACE(path);
        ASSERT_TRUE(f.at("error").is_null());
        auto h = las::read_header(io::File::open(path));
        EXPECT_EQ(f.at("point_count").get<std::uint64_t>(), h.point_count);
        for (int i = 0; i < 3; ++i) {
            EXPECT_EQ(f.at("bounds").at("min")[i].get<double>(), h.min[i]);
            EXPECT_EQ(f.at("bounds").at("max")[i].get<double>(), h.max[i]);
        }
        EXPECT_GT(f.at("chunk_point_count").get<std::uint64_t>(), 0u);
        if (path.find("/ky-") != std::string::npos) {
            EXPECT_EQ(f.at("crs").at("epsg"), 3089);
            EXPECT_EQ(f.at("crs").at("horizontal_unit"), "us_survey_foot");
            EXPECT_DOUBLE_EQ(f.at("crs").at("to_metres").get<double>(), 1200.0 / 3937.0);
            const auto& ll = f.at("lonlat_bounds");  // eastern Kentucky, through PROJ
            EXPECT_GT(ll.at("west").get<double>(), -85.5);
            EXPECT_LT(ll.at("east").get<double>(), -82.5);
            EXPECT_GT(ll.at("south").get<double>(), 37.0);
            EXPECT_LT(ll.at("north").get<double>(), 38.5);
        }
        if (path.find("/ign-") != std::string::npos) {  // France, Lambert-93
            EXPECT_GT(f.at("lonlat_bounds").at("west").get<double>(), -5.0);
            EXPECT_LT(f.at("lonlat_bounds").at("east").get<double>(), 10.0);
            EXPECT_GT(f.at("lonlat_bounds").at("south").get<double>(), 42.0);
        }
    }
}

TEST(InfoCommand, BadFileIsReportedAndOthersStillRead) {
    const auto good = (test::formats_dir() / "PDAL__PDAL/test__data__laz__autzen_trim.laz").string();
    const auto bad = (test::formats_dir() / "PDAL__PDAL/test__data__las__permutations__1.2-no-points.las").string();
    std::string err;
    int status = test::run_command(std::string(LIDARSCOUT_CLI) + " info " + good + " " + bad + " 2>&1 >/dev/null", err);
    EXPECT_EQ(status, 1);
    EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
    EXPECT_NE(err.find(bad), std::string::npos);
    EXPECT_NE(err.find("header announces 1065 points"), std::string::npos) << err;

    auto files = info_json(good + " " + bad, status);
    EXPECT_EQ(status, 1);
    ASSERT_EQ(files.size(), 2u);
    EXPECT_TRUE(files[0].at("error").is_null());
    EXPECT_EQ(files[0].at("point_count"), 110000);
    EXPECT_EQ(files[0].at("laz").at("compressor"), 2);
    EXPECT_TRUE(files[1].at("point_count").is_null());
    EXPECT_NE(files[1].at("error").get<std::string>().find(bad), std::string::npos);
}

TEST(InfoCommand, ChunksAndChunkPoints) {
    const auto path = (test::formats_dir() / "PDAL__PDAL/test__data__laz__autzen_trim.laz").string();
    int status = -1;
    auto f = info_json("--chunks " + path, status).at(0);
    EXPECT_EQ(status, 0);
    const auto want =
        test::read_json(test::formats_dir() / "expected/PDAL__PDAL__test__data__laz__autzen_trim.laz.json");
    ASSERT_EQ(f.at("chunks").size(), want.at("chunks").size());
    ASSERT_EQ(f.at("chunk_points").size(), want.at("chunk_points").size());
    for (std::size_t i = 0; i < f.at("chunks").size(); ++i) {
        for (const char* k : {"first_point", "point_count", "byte_offset", "byte_size"}) {
            EXPECT_EQ(f["chunks"][i][k], want["chunks"][i][k]);
        }
        for (const char* k : {"X", "Y", "Z", "intensity"}) {
            EXPECT_EQ(f["chunk_points"][i][k], want["chunk_points"][i][k]);
        }
        EXPECT_EQ(f["chunk_points"][i]["rgb"], want["chunk_points"][i]["rgb"]);
    }
}

// Strings from files reach JSON and the terminal as valid UTF-8: this file's GeoTIFF ASCII
// parameters are Latin-1 ("... basert p\xE5 EUREF89 ...").
TEST(InfoCommand, Latin1TextGivesValidUtf8) {
    const auto path = (test::formats_dir() / "gadomski__las-rs/tests__data__32-1-472-150-76.laz").string();
    std::string out;
    ASSERT_EQ(test::run_command(std::string(LIDARSCOUT_CLI) + " info --json " + path + " 2>&1", out), 0) << out;
    const auto j = nlohmann::json::parse(out);
    const std::string text = j.at(0).dump();
    EXPECT_NE(text.find("basert p\xC3\xA5 EUREF89"), std::string::npos)
        << "Latin-1 not decoded: " << text.substr(0, 400);
    ASSERT_EQ(test::run_command(std::string(LIDARSCOUT_CLI) + " info " + path + " 2>&1", out), 0) << out;
    EXPECT_NO_THROW((void)nlohmann::json(out).dump()) << "plain text is not valid UTF-8";
}

// `info --json` succeeds on every file the reference decodes.
TEST(InfoCommand, JsonForEveryDecodableFile) {
    std::string args;
    std::size_t files = 0;
    for (const auto& e : test::all_expected()) {
        if (e.json->at("reference_result") != "decodes") continue;
        args += " '" + e.file.string() + "'";
        ++files;
    }
    std::string out;
    ASSERT_EQ(test::run_command(std::string(LIDARSCOUT_CLI) + " info --json" + args + " 2>/dev/null", out), 0);
    const auto j = nlohmann::json::parse(out);
    ASSERT_EQ(j.size(), files);
    for (const auto& f : j) EXPECT_TRUE(f.at("error").is_null()) << f.at("path");
}

TEST(InfoCommand, MissingPathFails) {
    std::string out;
    EXPECT_EQ(test::run_command(std::string(LIDARSCOUT_CLI) + " info /nonexistent/x.laz 2>&1", out), 1);
    EXPECT_NE(out.find("/nonexistent/x.laz: no such file or folder"), std::string::npos) << out;
}

// Paths that give no tile are named, in --json too: a missing file, an empty folder, a text file
// that names nothing (a CSV of points, /etc/passwd); a virtual replica manifest gives its tiles.
TEST(InfoCommand, PathsWithoutTilesAreNamedAndManifestsGiveTheirTiles) {
    const auto dir = std::filesystem::temp_directory_path() / ("lidarscout_info_paths_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir / "empty");
    std::ofstream(dir / "pts.csv") << "x,y,z\n1,2,3\n4,5,6\n";
    int status = 0;
    auto j = info_json("/nonexistent/x.laz", status);
    EXPECT_EQ(status, 1);
    ASSERT_EQ(j.size(), 1u);
    EXPECT_EQ(j[0].at("path"), "/nonexistent/x.laz");
    std::string out;
    EXPECT_EQ(test::run_command(std::string(LIDARSCOUT_CLI) + " info " + (dir / "empty").string() + " " +
                                    (dir / "pts.csv").string() + " 2>&1", out), 1);
    EXPECT_NE(out.find("empty: no .las or .laz file in this folder"), std::string::npos) << out;
    EXPECT_NE(out.find("pts.csv: not a LAS/LAZ file nor a tile list (none of its 3 lines names a file, folder or URL)"),
              std::string::npos) << out;
    EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 2) << out;
    const auto tile = (test::surveys_dir() / "ign-lidar-hd-1km/Semis_2022_0906_6665_LA93_IGN69_ok.laz").string();
    ASSERT_EQ(test::run_command(std::string(LIDARSCOUT_CLI) + " synth replicate " + tile + " -o " +
                                    (dir / "rep").string() + " --grid 3x1 --virtual >/dev/null 2>&1", out), 0);
    j = info_json((dir / "rep/replicate.json").string(), status);
    EXPECT_EQ(status, 0);
    ASSERT_EQ(j.size(), 3u);
    EXPECT_EQ(info_json((dir / "rep").string(), status).size(), 3u) << "the replica's folder is the replica";
    EXPECT_EQ(status, 0);
    const auto min_x = [&](int i) { return j[i].at("bounds").at("min").at(0).get<double>(); };
    const double width = j[0].at("bounds").at("max").at(0).get<double>() - min_x(0);
    EXPECT_GT(min_x(1), min_x(0) + 0.9 * width);  // the second copy lies east of the first
    std::filesystem::remove_all(dir);
}

TEST(InfoCommand, CompoundCrsWithAVerticalPartProjLacksGetsLonLat) {
    int status = -1;
    const auto files =
        info_json((test::formats_dir() / "PDAL__PDAL" / "test__data__las__4_6_crop.las").string(), status);
    EXPECT_EQ(status, 0);
    ASSERT_EQ(files.size(), 1u);
    const auto& f = files[0];
    EXPECT_EQ(f.at("crs").at("epsg"), 2903);
    EXPECT_EQ(f.at("crs").at("vertical_epsg"), 5103);  // what the file says
    ASSERT_TRUE(f.at("lonlat_bounds").is_object()) << f.dump(2);
    EXPECT_NEAR(f.at("lonlat_bounds").at("west").get<double>(), -106.25, 0.01);  // New Mexico
    EXPECT_NE(f.at("crs").dump().find("PROJ does not know the vertical CRS EPSG:5103"), std::string::npos);
}

TEST(InfoCommand, Help) {
    std::string out;
    EXPECT_EQ(test::run_command(std::string(LIDARSCOUT_CLI) + " info --help", out), 0);
    EXPECT_NE(out.find("--chunks"), std::string::npos);
}

// The same files through nginx (range requests): the same output, byte for byte, but the path.
TEST(InfoCommand, RemoteFilesGiveTheSameOutputAsLocalOnes) {
    const auto& server = test::NginxServer::instance();
    for (const std::string rel : {"surveys/ky-woodford-county/5205000_3900000.laz",
                                  "formats/PDAL__PDAL/test__data__copc__1.2-with-color.copc.laz",
                                  "formats/PDAL__PDAL/test__data__las__1.2-with-color.las"}) {
        SCOPED_TRACE(rel);
        int local_status = -1, remote_status = -1;
        auto local = info_json("--checksum " + (test::data_dir() / rel).string(), local_status);
        auto remote = info_json("--checksum " + server.url(rel), remote_status);
        EXPECT_EQ(local_status, 0);
        EXPECT_EQ(remote_status, 0);
        ASSERT_EQ(remote.size(), 1u);
        EXPECT_EQ(remote[0].at("path"), server.url(rel));
        EXPECT_TRUE(remote[0].at("points_sha256").is_string());
        local[0].erase("path");
        remote[0].erase("path");
        EXPECT_EQ(local.dump(2), remote.dump(2));
    }
}

// Over HTTPS and HTTP/2 from a server whose CA is trusted by --cacert (or LIDARSCOUT_CACERT):
// the same output as the local file; without it, the certificate is refused.
TEST(InfoCommand, Http2WithAPrivateCaGivesTheSameOutputAsLocal) {
    const auto& server = test::NginxServer::instance();
    const std::string rel = "surveys/ky-woodford-county/5205000_3900000.laz";
    const std::string ca = server.ca_file().string();
    int local_status = -1, flag_status = -1, env_status = -1;
    auto local = info_json("--checksum " + (test::data_dir() / rel).string(), local_status);
    auto by_flag = info_json("--checksum --cacert " + ca + " " + server.https_url(rel), flag_status);
    setenv("LIDARSCOUT_CACERT", ca.c_str(), 1);
    auto by_env = info_json("--checksum " + server.https_url(rel), env_status);
    unsetenv("LIDARSCOUT_CACERT");
    EXPECT_EQ(local_status, 0);
    EXPECT_EQ(flag_status, 0);
    EXPECT_EQ(env_status, 0);
    ASSERT_EQ(by_flag.size(), 1u);
    ASSERT_EQ(by_env.size(), 1u);
    for (auto* j : {&local, &by_flag, &by_env}) (*j)[0].erase("path");
    EXPECT_EQ(local.dump(2), by_flag.dump(2));
    EXPECT_EQ(local.dump(2), by_env.dump(2));
    std::string out;
    EXPECT_EQ(test::run_command(std::string(LIDARSCOUT_CLI) + " info " + server.https_url(rel) + " 2>&1", out), 1);
    EXPECT_NE(out.find("certificate"), std::string::npos) << out;
}

// Credentials in a URL reach the server but never the output: not in JSON, not in errors.
TEST(InfoCommand, CredentialsInUrlsAreNeverPrinted) {
    const auto& server = test::NginxServer::instance();
    const std::string base = "http://reader:pa55word@127.0.0.1:" + std::to_string(server.port()) + "/";
    std::string out;
    const int status = test::run_command(std::string(LIDARSCOUT_CLI) + " info --json " + base +
                                             "surveys/ky-woodford-county/5205000_3900000.laz " + base +
                                             "surveys/missing.laz 2>&1",
                                         out);
    EXPECT_EQ(status, 1);
    EXPECT_EQ(out.find("pa55word"), std::string::npos) << out;
    EXPECT_NE(out.find(server.url("surveys/missing.laz") + ": at byte 0: HTTP status 404"), std::string::npos) << out;
    EXPECT_NE(out.find("\"point_count\": 1012412"), std::string::npos) << out;
}

// --threads 100000 started 32,383 threads and stalled the machine.
TEST(InfoCommand, HostileThreadCountIsCapped) {
    const auto err = std::filesystem::temp_directory_path() / ("lidarscout_info_threads_" + std::to_string(::getpid()));
    const auto run = test::run_measured(std::string(LIDARSCOUT_CLI) + " info --threads 100000 " +
                                            test::surveys_dir().string(), err);
    std::filesystem::remove(err);
    EXPECT_EQ(run.status, 0) << run.err;
    EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
    EXPECT_NE(run.err.find("--threads 100000 is more than this machine's " + std::to_string(max_threads()) +
                           " threads (4 per core, at most 256): using " + std::to_string(max_threads())),
              std::string::npos) << run.err;
    EXPECT_LE(run.max_threads, max_threads() + 32u);  // the pool and the header readers
    EXPECT_LT(run.max_rss_kb, 500 * 1024);
    std::string out;
    EXPECT_NE(test::run_command(std::string(LIDARSCOUT_CLI) + " info --threads -3 " + test::surveys_dir().string() +
                                    " 2>&1", out), 0) << out;
    EXPECT_NE(out.find("--threads: expects a whole number 0 or more, not '-3'"), std::string::npos) << out;
}

// Signed URLs (S3, GCS, Azure SAS, tokens): their secrets reach the server but never the
// output, in JSON or in errors.
TEST(InfoCommand, SignedQueryStringsAreNeverPrinted) {
    const auto& server = test::NginxServer::instance();
    const std::string query = "?X-Amz-Credential=CRED1&X-Amz-Security-Token=TOKEN1&X-Amz-Signature=SIGN1"
                              "&sig=SAS1&token=TOKEN2&X-Goog-Signature=GOOG1&access_token=TOKEN3&key=KEY1";
    std::string out;
    const int status = test::run_command(std::string(LIDARSCOUT_CLI) + " info --json '" +
                                             server.url("surveys/ky-woodford-county/5205000_3900000.laz") + query +
                                             "' '" + server.url("surveys/missing.laz") + query + "' 2>&1",
                                         out);
    EXPECT_EQ(status, 1);
    for (const char* secret : {"CRED1", "TOKEN1", "SIGN1", "SAS1", "TOKEN2", "GOOG1", "TOKEN3", "KEY1"}) {
        EXPECT_EQ(out.find(secret), std::string::npos) << secret << "\n" << out;
    }
    EXPECT_NE(out.find("X-Amz-Signature=REDACTED"), std::string::npos) << out;
    EXPECT_NE(out.find("HTTP status 404"), std::string::npos) << out;
    EXPECT_NE(out.find("\"point_count\": 1012412"), std::string::npos) << out;
}

// A password with an unencoded '#': one line with the hint, exit 1, the password not shown.
TEST(InfoCommand, PasswordWithAnUnencodedDelimiterIsRefusedWithAHint) {
    const auto& server = test::NginxServer::instance();
    const std::string url = "http://reader:pa#ss@127.0.0.1:" + std::to_string(server.port()) +
                            "/surveys/ky-woodford-county/5205000_3900000.laz";
    std::string out;
    EXPECT_EQ(test::run_command(std::string(LIDARSCOUT_CLI) + " info '" + url + "' 2>&1", out), 1);
    EXPECT_NE(out.find("percent-encode"), std::string::npos) << out;
    EXPECT_EQ(out.find("pa#ss"), std::string::npos) << out;
    EXPECT_EQ(out.find("reader"), std::string::npos) << out;
}

// --allow-origins and --min-rate take URLs or "*" and a rate; anything else is a usage error.
TEST(InfoCommand, RemoteOptionsAreChecked) {
    const std::string tile = (test::data_dir() / "surveys/ky-woodford-county/5205000_3900000.laz").string();
    std::string out;
    EXPECT_NE(test::run_command(std::string(LIDARSCOUT_CLI) + " info --allow-origins nope " + tile + " 2>&1", out), 0);
    EXPECT_NE(out.find("--allow-origins: \"nope\" is not an http(s) URL"), std::string::npos) << out;
    EXPECT_NE(test::run_command(std::string(LIDARSCOUT_CLI) + " info --min-rate 1x " + tile + " 2>&1", out), 0);
    EXPECT_NE(out.find("--min-rate"), std::string::npos) << out;
    EXPECT_EQ(test::run_command(std::string(LIDARSCOUT_CLI) + " info --min-rate 64K --allow-origins '*,https://a' " +
                                    tile + " 2>&1",
                                out),
              0)
        << out;
}

// Flipped bytes in every cached range, then a 1 GiB file in place of one entry: the same
// points_sha256 as the local file each time (the entries dropped, named, fetched again).
TEST(InfoCommand, DamagedRangeCacheEntriesAreFetchedAgain) {
    namespace fs = std::filesystem;
    const auto& server = test::NginxServer::instance();
    const std::string rel = "surveys/ky-woodford-county/5205000_3900000.laz";
    const fs::path cache = fs::temp_directory_path() / ("lidarscout_info_cache_" + std::to_string(::getpid()));
    const std::string cli = "XDG_CACHE_HOME=" + cache.string() + " " + LIDARSCOUT_CLI;
    int status = -1;
    const auto local = info_json("--checksum " + (test::data_dir() / rel).string(), status);
    const std::string expected = local.at(0).at("points_sha256");
    auto checksum = [&](std::string& err) {
        std::string out;
        const int rc = test::run_command(cli + " info --json --checksum " + server.url(rel) + " 2>" +
                                             (cache / "stderr").string(), out);
        EXPECT_EQ(rc, 0);
        std::ifstream in(cache / "stderr");
        err.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
        return nlohmann::json::parse(out).at(0).at("points_sha256").get<std::string>();
    };
    auto entries = [&] {
        std::vector<fs::path> found;
        for (const auto& e : fs::recursive_directory_iterator(cache / "lidarscout" / "http")) {
            if (e.is_regular_file()) found.push_back(e.path());
        }
        return found;
    };
    fs::create_directories(cache);
    std::string err;
    EXPECT_EQ(checksum(err), expected);
    const auto stored = entries();
    ASSERT_FALSE(stored.empty());
    for (const auto& entry : stored) {
        std::fstream f(entry, std::ios::in | std::ios::out | std::ios::binary);
        f.seekp(static_cast<std::streamoff>(fs::file_size(entry) / 2));
        f.write("XXXXXXXXXX", 10);
    }
    EXPECT_EQ(checksum(err), expected);
    EXPECT_NE(err.find("was dropped and fetched again: part 0 does not match its SHA-256"), std::string::npos) << err;
    fs::resize_file(entries().front(), 1ull << 30);
    EXPECT_EQ(checksum(err), expected);
    EXPECT_NE(err.find("bytes, is more than its ranges can hold"), std::string::npos) << err;
    fs::remove_all(cache);
}

}  // namespace
}  // namespace lidarscout
