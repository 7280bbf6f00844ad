// `lidarscout scan --json`: on each survey folder, as many chunk points as the files' chunk
// tables hold (LAS: ceil(n / 50,000)) and the headers' bounds in metres (Kentucky and
// Raleigh: US survey feet).
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>

#include "dataset/file_search.hpp"
#include "dataset/tile.hpp"
#include "io/file.hpp"
#include "net/fault_server.hpp"
#include "nginx_server.hpp"
#include "s3_server.hpp"
#include "test_data.hpp"

namespace lidarscout {
namespace {

nlohmann::json scan_json(const std::string& args, int& status, const std::string& environment = "") {
    std::string out;
    status = test::run_command(environment + " " + LIDARSCOUT_CLI + " scan --json " + args + " 2>/dev/null", out);
    return nlohmann::json::parse(out);
}

std::uint64_t expected_chunk_points(const dataset::Tile& t) {
    if (!t.compressed()) return (t.header.point_count + 49'999) / 50'000;
    return static_cast<std::uint64_t>(std::count_if(t.chunks()->begin(), t.chunks()->end(),
                                                    [](const auto& c) { return c.point_count > 0; }));
}

TEST(ScanCommand, EverySurveyFolderMatchesItsChunkTablesAndHeaders) {
    for (const auto& entry : std::filesystem::directory_iterator(test::surveys_dir())) {
        if (!entry.is_directory()) continue;
        SCOPED_TRACE(entry.path().string());
        const auto name = entry.path().filename().string();
        const bool feet = name.rfind("ky-", 0) == 0 || name == "nc-raleigh-ept";  // EPSG:3089, EPSG:2264: US ft
        const double f = feet ? 1200.0 / 3937.0 : 1.0;
        std::uint64_t chunk_points = 0;
        double min_x = std::numeric_limits<double>::infinity(), max_y = -min_x, max_z = -min_x;
        const auto files = dataset::find_point_cloud_files({entry.path().string()}).files;
        for (const auto& path : files) {
            const auto t = dataset::read_tile(io::File::open(path));
            chunk_points += expected_chunk_points(t);
            min_x = std::min(min_x, t.header.min[0] * f);
            max_y = std::max(max_y, t.header.max[1] * f);
            max_z = std::max(max_z, t.header.max[2] * f);
        }
        int status = -1;
        const auto j = scan_json(entry.path().string(), status);
        EXPECT_EQ(status, 0);
        EXPECT_EQ(j.at("tiles").get<std::size_t>(), files.size());
        EXPECT_TRUE(j.at("skipped").empty());
        EXPECT_EQ(j.at("chunk_points").get<std::uint64_t>(), chunk_points);
        EXPECT_GT(j.at("patches").get<std::size_t>(), 0u);
        EXPECT_DOUBLE_EQ(j.at("bounds").at("min_x").get<double>(), min_x);
        EXPECT_DOUBLE_EQ(j.at("bounds").at("max_y").get<double>(), max_y);
        EXPECT_DOUBLE_EQ(j.at("bounds").at("max_z").get<double>(), max_z);
        EXPECT_GE(j.at("seconds_headers").get<double>(), 0.0);
        EXPECT_GE(j.at("seconds_chunk_points").get<double>(), 0.0);
    }
}

// Kentucky (US feet) and the ISPRS sites (UTM 32N) opened together: with --crs the Kentucky
// tiles are reprojected to UTM 32N too, so the whole lies in that zone's metres.
TEST(ScanCommand, MixedCrsReprojectedToTheCrsAskedFor) {
    int status = -1;
    const std::string ky = (test::surveys_dir() / "ky-red-river-gorge").string();
    const auto alone = scan_json(ky + " --crs EPSG:32617", status);  // Kentucky lies in UTM zone 17N
    ASSERT_EQ(status, 0);
    const auto& b = alone.at("bounds");
    EXPECT_GT(b.at("min_x").get<double>(), 200'000.0);  // UTM eastings
    EXPECT_LT(b.at("max_x").get<double>(), 800'000.0);
    EXPECT_GT(b.at("min_y").get<double>(), 4'000'000.0);  // ~37.8 degrees north
    EXPECT_LT(b.at("max_y").get<double>(), 4'300'000.0);
    EXPECT_TRUE(alone.at("warnings").empty());
    const auto both = scan_json(ky + " " + (test::surveys_dir() / "isprs-filter-test-sites").string(), status);
    ASSERT_EQ(status, 0);
    ASSERT_EQ(both.at("warnings").size(), 1u);
    EXPECT_NE(both.at("warnings")[0].get<std::string>().find("reprojected to EPSG:32632"), std::string::npos);
    // the same, levelled: about the whole dataset (no file, no offset)
    ASSERT_EQ(both.at("diagnostics").size(), 1u);
    const auto& d = both.at("diagnostics")[0];
    EXPECT_EQ(d.at("level"), "warning");
    EXPECT_TRUE(d.at("file").is_null());
    EXPECT_TRUE(d.at("offset").is_null());
    EXPECT_EQ(d.at("message"), both.at("warnings")[0]);
    EXPECT_EQ(both.at("chunk_points_failed"), 0);
}

TEST(ScanCommand, SkippedFilesAreListedAndTheRestScanned) {
    std::string out;
    const int status = test::run_command(std::string(LIDARSCOUT_CLI) + " scan --json /nonexistent/x.laz " +
                                   (test::surveys_dir() / "ky-woodford-county").string() + " 2>/dev/null", out);
    const auto j = nlohmann::json::parse(out);
    EXPECT_EQ(status, 0);
    EXPECT_EQ(j.at("tiles").get<int>(), 1);
    ASSERT_EQ(j.at("skipped").size(), 1u);
    EXPECT_NE(j.at("skipped")[0].at("error").get<std::string>().find("/nonexistent/x.laz"), std::string::npos);
}

TEST(ScanCommand, NothingReadableIsAnError) {
    std::string out;
    const int status = test::run_command(std::string(LIDARSCOUT_CLI) + " scan /nonexistent 2>&1", out);
    EXPECT_EQ(status, 1);
    EXPECT_NE(out.find("/nonexistent"), std::string::npos);
}

// A catalog item whose pc:count is "lots" (issue 53): its tile is read, the summary skips none, and one
// warning line names the item and its catalog.
TEST(ScanCommand, ACatalogItemWithABadCountIsReadNotSkipped) {
    const auto dir = std::filesystem::temp_directory_path() / ("lidarscout_scan_lots_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    const auto strip = [](const char* name) { return (test::surveys_dir() / "lasr-bcts-strips" / name).string(); };
    const nlohmann::json vpc = {
        {"type", "FeatureCollection"},
        {"features", {{{"type", "Feature"}, {"id", "b1"}, {"properties", {{"pc:count", "lots"}}},
                       {"assets", {{"data", {{"href", strip("bcts_1.laz")}}}}}},
                      {{"type", "Feature"}, {"id", "b2"}, {"properties", nlohmann::json::object()},
                       {"assets", {{"data", {{"href", strip("bcts_2.laz")}}}}}}}}};
    const std::string path = (dir / "lots.vpc").string();
    std::ofstream(path) << vpc.dump();
    std::string out;
    const int status = test::run_command(std::string(LIDARSCOUT_CLI) + " scan " + path + " 2>&1", out);
    std::filesystem::remove_all(dir);
    EXPECT_EQ(status, 0) << out;
    EXPECT_NE(out.find("tiles:         2 read, 0 skipped, "), std::string::npos) << out;
    const std::string line = "lidarscout: warning: item 'b1' in " + path +
                             ": \"pc:count\" is a string, not a count (a whole number, 0 or more); the tile's "
                             "header is read instead\n";
    EXPECT_NE(out.find(line), std::string::npos) << out;
    EXPECT_EQ(std::count(out.begin(), out.end(), '\n') - 5, 1) << "one line besides the summary's five:\n" << out;
}

// scan --json without the timing and network fields.
nlohmann::json without_timings(nlohmann::json j) {
    for (const char* key : {"chunk_points_per_second", "seconds_chunk_points", "seconds_headers", "requests",
                            "bytes", "retries", "requests_per_tile", "bytes_per_tile", "opens_in_one_request",
                            "open_fallbacks"}) {
        j.erase(key);
    }
    return j;
}

// Lines of nginx's access log so far.
std::size_t logged_requests(const std::filesystem::path& log) {
    std::ifstream in(log);
    const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    return static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n'));
}

// A remote tile list with relative URLs scans like the local folders: the same JSON but the
// timings; a tile's chunk points are one multi-range request, so a tile costs at most 3
// requests (head, tail, chunk points); a second look with the range cache costs 1 (the head,
// which revalidates the file).
TEST(ScanCommand, RemoteTileListGivesTheSameResultAsLocalFolders) {
    const auto& server = test::NginxServer::instance();
    // (tiles whose header and VLRs fit in the first 2 KiB and chunk table in the last: the IGN
    // tiles' WKT VLRs take one more request)
    const std::vector<std::string> surveys = {"ky-jmo335-eastern-kentucky", "isprs-filter-test-sites",
                                              "ky-red-river-gorge"};
    std::ofstream list(server.lists_dir() / "surveys.txt");
    std::string local_args;
    std::size_t tiles = 0;
    for (const auto& s : surveys) {
        local_args += " " + (test::surveys_dir() / s).string();
        for (const auto& f : dataset::find_point_cloud_files({(test::surveys_dir() / s).string()}).files) {
            list << "# " << s << "\n../surveys/" << s << "/" << std::filesystem::path(f).filename().string() << "\n";
            ++tiles;
        }
    }
    list.close();
    const auto cache = std::filesystem::temp_directory_path() / ("lidarscout_scan_cache_" + std::to_string(::getpid()));
    const std::string remote_args = server.url("lists/surveys.txt");
    int status = -1;
    const auto local = scan_json(local_args, status);
    ASSERT_EQ(status, 0);
    for (const std::size_t most_requests : {3 * tiles + 1, tiles + 1}) {  // the list, then per tile
        const std::size_t before = logged_requests(server.access_log());
        const auto remote = scan_json(remote_args + " --cache-size 100M", status, "XDG_CACHE_HOME=" + cache.string());
        EXPECT_EQ(status, 0);
        EXPECT_EQ(without_timings(remote).dump(2), without_timings(local).dump(2));
        EXPECT_LE(logged_requests(server.access_log()) - before, most_requests);
    }
    std::filesystem::remove_all(cache);
}

// --io-threads 100000 aborted ("terminate called without an active exception").
TEST(ScanCommand, HostileIoThreadCountIsCapped) {
    std::string out;
    const int status = test::run_command(std::string(LIDARSCOUT_CLI) + " scan --io-threads 100000 " +
                                             (test::surveys_dir() / "ky-woodford-county").string() + " 2>&1", out);
    EXPECT_EQ(status, 0) << out;
    EXPECT_NE(out.find("--io-threads 100000 is more than"), std::string::npos) << out;
    EXPECT_EQ(out.find("terminate"), std::string::npos) << out;
}

// A server that answers a tile's header and chunk table, then 404 for everything else: every
// chunk point fails, and scan says so by its exit status.
TEST(ScanCommand, EveryChunkPointFailedIsAnError) {
    const auto path = test::data_dir() / "surveys/ky-woodford-county/5205000_3900000.laz";
    std::ifstream in(path, std::ios::binary);
    test::FaultServer server({std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()});
    server.answer_first = 2;  // the head and the tail
    std::string out;
    const std::string url = server.url().substr(0, server.url().rfind('/')) + "/tile.laz";  // (any path serves)
    const int status =
        test::run_command(std::string(LIDARSCOUT_CLI) + " scan --json --cache-size 0 " + url + " 2>/dev/null", out);
    EXPECT_EQ(status, 1);
    const auto j = nlohmann::json::parse(out);
    EXPECT_EQ(j.at("tiles"), 1);
    EXPECT_EQ(j.at("chunk_points"), 0);
    EXPECT_GT(j.at("chunk_points_failed").get<int>(), 0);
}

// An s3 prefix holding two surveys (put on the test S3 server, which checks AWS Signature V4)
// scans like the local folders; a wrong secret is an error naming the bucket, key and S3 error
// code, and the secret appears nowhere in what the command writes.
TEST(ScanCommand, S3PrefixGivesTheSameResultAsLocalFoldersAndNeverShowsTheSecret) {
    auto& server = test::S3Server::instance();
    const std::vector<std::string> surveys = {"isprs-filter-test-sites", "ky-woodford-county"};
    std::string local_args;
    for (const auto& s : surveys) {
        local_args += " " + (test::surveys_dir() / s).string();
        for (const auto& f : dataset::find_point_cloud_files({(test::surveys_dir() / s).string()}).files) {
            server.put_file("tiles", "scan/" + s + "/" + std::filesystem::path(f).filename().string(), f);
        }
    }
    const std::string aws = "AWS_SHARED_CREDENTIALS_FILE=/dev/null AWS_ENDPOINT_URL=" + server.endpoint() +
                            " AWS_ACCESS_KEY_ID=" + test::S3Server::kKey + " AWS_SECRET_ACCESS_KEY=";
    int status = -1;
    const auto local = scan_json(local_args, status);
    ASSERT_EQ(status, 0);
    const auto remote = scan_json("s3://tiles/scan/ --cache-size 0", status, aws + test::S3Server::kSecret);
    EXPECT_EQ(status, 0);
    EXPECT_EQ(without_timings(remote).dump(2), without_timings(local).dump(2));

    std::string out;
    status = test::run_command(aws + "wrong-cli-secret-91 " + LIDARSCOUT_CLI +
                                   " scan --cache-size 0 s3://tiles/scan/ky-woodford-county/5205000_3900000.laz 2>&1",
                               out);
    EXPECT_NE(status, 0);
    EXPECT_NE(out.find("SignatureDoesNotMatch"), std::string::npos) << out;
    EXPECT_NE(out.find("bucket \"tiles\", key \"scan/ky-woodford-county/5205000_3900000.laz\""), std::string::npos)
        << out;
    EXPECT_EQ(out.find("wrong-cli-secret-91"), std::string::npos) << out;
    status =
        test::run_command(aws + "wrong-cli-secret-91 " + LIDARSCOUT_CLI + " scan --json s3://tiles/scan/ 2>&1", out);
    EXPECT_NE(status, 0);
    EXPECT_NE(out.find("SignatureDoesNotMatch"), std::string::npos) << out;
    EXPECT_EQ(out.find("wrong-cli-secret-91"), std::string::npos) << out;
}

// `scan s3://tiles/bcts` (no trailing slash) where bcts/ holds the BCTS strips (issue 53): scanned as the
// prefix, like a local folder, with a note saying so; a key that is neither object nor prefix is the
// S3 error alone (NoSuchKey, bucket and key).
TEST(ScanCommand, AnS3PrefixWithoutItsSlashIsScannedAsThePrefix) {
    auto& server = test::S3Server::instance();
    const auto strips = test::surveys_dir() / "lasr-bcts-strips";
    for (const auto& f : dataset::find_point_cloud_files({strips.string()}).files) {
        server.put_file("tiles", "bcts/" + std::filesystem::path(f).filename().string(), f);
    }
    const std::string aws = "AWS_SHARED_CREDENTIALS_FILE=/dev/null AWS_ENDPOINT_URL=" + server.endpoint() +
                            " AWS_ACCESS_KEY_ID=" + test::S3Server::kKey + " AWS_SECRET_ACCESS_KEY=" +
                            test::S3Server::kSecret + " ";
    int status = -1;
    const auto local = scan_json(strips.string(), status);
    ASSERT_EQ(status, 0);
    auto remote = scan_json("s3://tiles/bcts --cache-size 0", status, aws);
    EXPECT_EQ(status, 0);
    ASSERT_EQ(remote.at("diagnostics").size(), 1u) << remote.dump(1);
    EXPECT_EQ(remote.at("diagnostics")[0].at("level"), "note");
    EXPECT_EQ(remote.at("diagnostics")[0].at("message"),
              "s3://tiles/bcts is not an object: opened as the prefix s3://tiles/bcts/ (the objects under it)");
    for (const char* key : {"diagnostics", "warnings"}) remote.erase(key);
    auto plain = without_timings(local);
    for (const char* key : {"diagnostics", "warnings"}) plain.erase(key);
    EXPECT_EQ(without_timings(remote).dump(2), plain.dump(2));
    std::string out;
    status = test::run_command(aws + LIDARSCOUT_CLI + " scan --cache-size 0 s3://tiles/bctz 2>&1", out);
    EXPECT_EQ(status, 1) << out;
    EXPECT_NE(out.find("NoSuchKey"), std::string::npos) << out;
    EXPECT_NE(out.find("bucket \"tiles\", key \"bctz\""), std::string::npos) << out;
    EXPECT_EQ(out.find("prefix"), std::string::npos) << out;
}

// --requester-pays (and AWS_REQUEST_PAYER=requester) put x-amz-request-payer on every request of
// an s3:// dataset; without either, no request has it.
TEST(ScanCommand, RequesterPaysReachesTheServer) {
    const auto path = test::data_dir() / "surveys/ky-woodford-county/5205000_3900000.laz";
    std::ifstream in(path, std::ios::binary);
    test::FaultServer server({std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()});
    const std::string endpoint = server.url().substr(0, server.url().rfind('/'));
    const std::string env = "AWS_SHARED_CREDENTIALS_FILE=/dev/null AWS_ACCESS_KEY_ID=AKIATEST "
                            "AWS_SECRET_ACCESS_KEY=cli-secret-3 AWS_ENDPOINT_URL=" + endpoint + " ";
    const auto paid = [&] {
        std::size_t n = 0;
        for (const auto& head : server.requests_seen()) {
            n += head.find("x-amz-request-payer: requester") != std::string::npos;
        }
        return n;
    };
    std::string out;
    const std::string scan = std::string(LIDARSCOUT_CLI) + " scan --cache-size 0 s3://bucket/tile.laz";
    ASSERT_EQ(test::run_command(env + scan + " 2>&1", out), 0) << out;
    const auto requests = server.requests_seen().size();
    EXPECT_GE(requests, 3u);
    EXPECT_EQ(paid(), 0u);
    ASSERT_EQ(test::run_command(env + scan + " --requester-pays 2>&1", out), 0) << out;
    EXPECT_EQ(paid(), server.requests_seen().size() - requests);
    ASSERT_EQ(test::run_command(env + "AWS_REQUEST_PAYER=requester " + scan + " 2>&1", out), 0) << out;
    EXPECT_EQ(paid(), server.requests_seen().size() - requests);  // every request of the last two runs
    for (const auto& head : server.requests_seen()) EXPECT_EQ(head.find("cli-secret-3"), std::string::npos) << head;
}

}  // namespace
}  // namespace lidarscout
