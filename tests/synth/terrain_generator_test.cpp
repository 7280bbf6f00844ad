// generate_terrain and `lidarscout synth terrain`: the same options give the same bytes
// (whatever the threads), another seed other bytes; every tile passes `info` and decodes
// fully; the statistics are those of a landscape (density, classes, colours, canopy above
// the ground, chunk points spread over the tile); the output folder is guarded.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>

#include "core/error.hpp"
#include "core/sha256.hpp"
#include "core/thread_pool.hpp"
#include "dataset/chunk_points.hpp"
#include "dataset/point_reader.hpp"
#include "dataset/tile.hpp"
#include "io/file.hpp"
#include "las/point_format.hpp"
#include "synth/terrain_generator.hpp"
#include "synth/terrain_model.hpp"
#include "synth/terrain_patch.hpp"
#include "test_data.hpp"

namespace lidarscout {
namespace {

namespace fs = std::filesystem;

std::string file_sha256(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::vector<std::uint8_t> bytes{std::istreambuf_iterator<char>(in), {}};
    Sha256 sha;
    sha.update(bytes);
    return sha.hex_digest();
}

std::map<std::string, std::string> folder_sha256(const fs::path& dir) {
    std::map<std::string, std::string> out;
    for (const auto& e : fs::directory_iterator(dir)) out[e.path().filename().string()] = file_sha256(e.path());
    return out;
}

// One demo of 1 km x 1 km at 2 points/m2 (4 tiles), generated once for the suite.
class TerrainGenerator : public ::testing::Test {
protected:
    static fs::path root() { return fs::temp_directory_path() / ("lidarscout_terrain_" + std::to_string(::getpid())); }
    static void SetUpTestSuite() {
        fs::create_directories(root());
        options_.km = 1;
        options_.density = 2;
        ThreadPool pool(2);
        result_ = synth::generate_terrain(options_, (root() / "demo").string(), pool);
    }
    static void TearDownTestSuite() { fs::remove_all(root()); }

    static inline synth::TerrainOptions options_;
    static inline synth::TerrainResult result_;
};

TEST_F(TerrainGenerator, TilesManifestAndHeaders) {
    ASSERT_EQ(result_.tiles.size(), 4u);
    EXPECT_TRUE(fs::exists(root() / "demo" / synth::kTerrainManifest));
    std::uint64_t points = 0, bytes = 0;
    for (const auto& t : result_.tiles) {
        EXPECT_EQ(fs::path(t.path).filename().string(), synth::terrain_tile_name(t.ix, t.iy));
        EXPECT_EQ(fs::file_size(t.path), t.bytes);
        points += t.points;
        bytes += t.bytes;
        auto file = io::File::open(t.path);
        const auto tile = dataset::read_tile(file);
        EXPECT_TRUE(tile.warnings().empty()) << tile.warnings().front().message;
        EXPECT_EQ(tile.header.version_string(), "1.4");
        EXPECT_EQ(tile.header.point_format, 7);
        EXPECT_EQ(tile.header.point_count, t.points);
        EXPECT_EQ(tile.header.generating_software, synth::kTerrainSoftware);
        EXPECT_TRUE(tile.header.global_encoding & 16);  // WKT
        EXPECT_TRUE(tile.header.global_encoding & 1);   // adjusted standard GPS time
        ASSERT_TRUE(tile.laz());
        EXPECT_EQ(tile.laz()->compressor, 3);
        EXPECT_EQ(tile.laz()->chunk_size, 50'000u);
        EXPECT_EQ(tile.chunks()->size(), (t.points + 49'999) / 50'000);
        EXPECT_EQ(tile.crs().epsg, 25832);
        EXPECT_EQ(tile.crs().vertical_epsg, 7837);
        EXPECT_EQ(tile.crs().horizontal_unit, las::LinearUnit::Metre);
        EXPECT_EQ(tile.crs().z_to_metres(), 1.0);
        EXPECT_TRUE(tile.crs().warnings.empty());
        EXPECT_NEAR(tile.header.min[0], 500'000.0 + t.ix * 500.0, 0.5);  // points reach the tile's edges
        EXPECT_LT(tile.header.max[0], 500'000.0 + (t.ix + 1) * 500.0);
        EXPECT_GT(tile.header.max[0], 500'000.0 + (t.ix + 1) * 500.0 - 0.5);
        EXPECT_EQ(tile.header.points_by_return[0] + tile.header.points_by_return[1] + tile.header.points_by_return[2],
                  t.points);
    }
    EXPECT_EQ(points, result_.points);
    EXPECT_EQ(bytes, result_.bytes);
}

// Decodes every point of every tile and checks the statistics a landscape should have.
TEST_F(TerrainGenerator, DecodesFullyWithPlausibleStatistics) {
    ThreadPool pool(2);
    const synth::TerrainModel model(options_.seed, result_.area);
    std::map<int, std::uint64_t> classes;
    std::uint64_t points = 0, multi = 0, low_canopy = 0, canopy = 0;
    double sum[3] = {}, sum2[3] = {};
    std::set<std::uint64_t> colours;
    for (const auto& t : result_.tiles) {
        auto file = io::File::open(t.path);
        const auto tile = dataset::read_tile(file);
        const auto& format = las::point_format_info(7);
        const synth::TerrainPatch patch(model, tile.header.min[0] - 1, tile.header.min[1] - 1, tile.header.max[0] + 1,
                                        tile.header.max[1] + 1);
        std::array<std::int32_t, 3> lo{INT32_MAX, INT32_MAX, INT32_MAX}, hi{INT32_MIN, INT32_MIN, INT32_MIN};
        std::uint64_t n = 0;
        dataset::for_each_record_batch(file, tile, pool, [&](std::uint64_t, std::span<const std::uint8_t> records) {
            for (std::size_t i = 0; i < records.size() / format.size; ++i) {
                const auto p = las::decode_point(records.subspan(i * format.size, format.size), format, tile.header);
                ++n;
                lo = {std::min(lo[0], p.X), std::min(lo[1], p.Y), std::min(lo[2], p.Z)};
                hi = {std::max(hi[0], p.X), std::max(hi[1], p.Y), std::max(hi[2], p.Z)};
                ++classes[p.classification];
                multi += p.number_of_returns > 1;
                for (int c = 0; c < 3; ++c) {
                    sum[c] += p.rgb[c];
                    sum2[c] += double(p.rgb[c]) * p.rgb[c];
                }
                if (colours.size() < 100'000) {
                    colours.insert((std::uint64_t(p.rgb[0]) << 32) | (std::uint64_t(p.rgb[1]) << 16) | p.rgb[2]);
                }
                if (p.classification >= 3 && p.classification <= 5) {
                    // Vegetation stands above the terrain by at least its class's height.
                    const double above = p.z - patch.ground(p.x, p.y);
                    const double least = p.classification == 5 ? 5.0 : p.classification == 4 ? 2.0 : 0.0;
                    ASSERT_GE(above, least - 0.02) << p.x << " " << p.y << " class " << int(p.classification);
                    ++canopy;
                    low_canopy += p.return_number < p.number_of_returns;
                }
            }
        });
        EXPECT_EQ(n, tile.header.point_count);
        for (int a = 0; a < 3; ++a) {  // the header's bounds are the points' bounds
            EXPECT_DOUBLE_EQ(tile.header.min[a], lo[a] * tile.header.scale[a] + tile.header.offset[a]);
            EXPECT_DOUBLE_EQ(tile.header.max[a], hi[a] * tile.header.scale[a] + tile.header.offset[a]);
        }
        points += n;
    }
    EXPECT_EQ(points, result_.points);
    // Density: within 15% of the request (the returns per pulse depend on the tree cover).
    const double density = double(points) / (result_.area.size() * result_.area.size());
    EXPECT_NEAR(density, options_.density, 0.15 * options_.density);
    // Ground, vegetation, buildings, water, roads and the bridge are all there.
    for (int c : {2, 5, 6, 9, 11, 17}) EXPECT_GT(classes[c], 0u) << "class " << c;
    EXPECT_GT(classes[2], points / 2);
    EXPECT_GT(classes[3] + classes[4] + classes[5], points / 20);
    EXPECT_GT(classes[6], points / 1000);
    for (const auto& [c, n] : classes) EXPECT_TRUE(std::set<int>({2, 3, 4, 5, 6, 9, 11, 17}).count(c)) << c;
    // Several returns under trees; colours vary.
    EXPECT_GT(multi, points / 20);
    EXPECT_GT(low_canopy, canopy / 10);
    EXPECT_GT(colours.size(), 10'000u);
    for (int c = 0; c < 3; ++c) {
        const double mean = sum[c] / points, sd = std::sqrt(sum2[c] / points - mean * mean);
        EXPECT_GT(mean, 5'000.0);
        EXPECT_LT(mean, 40'000.0);
        EXPECT_GT(sd, 1'500.0) << "channel " << c;
    }
}

// Chunk points (the raw first point of each chunk) are spread over the tile like a real
// scan's: along the flight strips, across several of them.
TEST_F(TerrainGenerator, ChunkPointsSpreadOverTheTile) {
    for (const auto& t : result_.tiles) {
        auto file = io::File::open(t.path);
        const auto tile = dataset::read_tile(file);
        const auto cps = dataset::read_chunk_points(file, tile);
        ASSERT_EQ(cps.size(), tile.chunks()->size());
        double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
        std::set<int> strips;
        for (const auto& c : cps) {
            x0 = std::min(x0, c.point.x);
            x1 = std::max(x1, c.point.x);
            y0 = std::min(y0, c.point.y);
            y1 = std::max(y1, c.point.y);
            strips.insert(c.point.point_source_id);
        }
        EXPECT_GT(x1 - x0, 150.0) << t.path;
        EXPECT_GT(y1 - y0, 300.0) << t.path;
        EXPECT_GE(strips.size(), 2u) << t.path;
    }
}

TEST_F(TerrainGenerator, SameSeedSameBytesWhateverTheThreads) {
    synth::TerrainOptions o;
    o.km = 1;
    o.density = 0.4;
    ThreadPool one(1), three(3);
    synth::generate_terrain(o, (root() / "a").string(), one);
    synth::generate_terrain(o, (root() / "b").string(), three);
    const auto a = folder_sha256(root() / "a"), b = folder_sha256(root() / "b");
    EXPECT_EQ(a.size(), 5u);  // four tiles and the manifest
    EXPECT_EQ(a, b);
    o.seed = 2;
    synth::generate_terrain(o, (root() / "c").string(), three);
    const auto c = folder_sha256(root() / "c");
    EXPECT_NE(a.at("demo_000_000.laz"), c.at("demo_000_000.laz"));
    // Running again into the same folder replaces the demo with the same bytes.
    synth::generate_terrain(o, (root() / "c").string(), three);
    EXPECT_EQ(folder_sha256(root() / "c"), c);
}

TEST_F(TerrainGenerator, GuardsTheOutputFolder) {
    synth::TerrainOptions o;
    o.km = 0.5;
    o.density = 0.2;
    ThreadPool pool(2);
    const auto dir = root() / "guard";
    fs::create_directories(dir);
    {
        std::ofstream(dir / "demo_000_000.laz") << "not a demo";
    }
    EXPECT_THROW(synth::generate_terrain(o, dir.string(), pool), Error);
    EXPECT_EQ(fs::file_size(dir / "demo_000_000.laz"), 10u);  // untouched
    fs::remove(dir / "demo_000_000.laz");
    {
        std::ofstream(dir / "survey.las") << "someone's data";
    }
    try {
        synth::generate_terrain(o, dir.string(), pool);
        ADD_FAILURE() << "a foreign LAS file was accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("survey.las"), std::string::npos) << e.what();
    }
    EXPECT_EQ(fs::file_size(dir / "survey.las"), 14u);
    EXPECT_THROW(synth::generate_terrain(o, (dir / "survey.las" / "x").string(), pool), Error);
}

TEST(TerrainOptions, Validation) {
    synth::TerrainOptions o;
    EXPECT_EQ(synth::terrain_area(o).tiles, 8u);
    o.km = 1.2;
    EXPECT_EQ(synth::terrain_area(o).tiles, 3u);  // rounded up to whole tiles
    o.km = 0.1;
    EXPECT_EQ(synth::terrain_area(o).tiles, 1u);
    for (double km : {0.0, -1.0, std::nan(""), 1e6}) {
        o.km = km;
        EXPECT_THROW(synth::terrain_area(o), Error) << km;
    }
    o.km = 1;
    for (double d : {0.0, -2.0, std::nan(""), 1e5}) {
        o.density = d;
        EXPECT_THROW(synth::terrain_area(o), Error) << d;
    }
    EXPECT_EQ(synth::terrain_tile_name(3, 12), "demo_003_012.laz");
}

TEST(TerrainCommand, JsonSummaryAndInfo) {
    const auto dir = fs::temp_directory_path() / ("lidarscout_terrain_cli_" + std::to_string(::getpid()));
    std::string out;
    ASSERT_EQ(test::run_command(std::string(LIDARSCOUT_CLI) + " synth terrain -o " + dir.string() +
                                    " --km 0.5 --density 0.5 --seed 7 --threads 2 --json",
                                out),
              0)
        << out;
    const auto j = nlohmann::json::parse(out);
    EXPECT_EQ(j.at("tiles"), 1);
    EXPECT_EQ(j.at("seed"), 7);
    EXPECT_EQ(j.at("km"), 0.5);
    EXPECT_NEAR(j.at("points_per_m2").get<double>(), 0.5, 0.1);
    ASSERT_EQ(j.at("files").size(), 1u);
    const std::string tile = j.at("files").at(0).at("path");
    EXPECT_EQ(j.at("files").at(0).at("points"), j.at("points"));
    ASSERT_EQ(test::run_command(std::string(LIDARSCOUT_CLI) + " info --json --checksum " + tile, out), 0) << out;
    const auto info = nlohmann::json::parse(out).at(0);
    EXPECT_TRUE(info.at("error").is_null());
    EXPECT_EQ(info.at("crs").at("epsg"), 25832);
    EXPECT_EQ(info.at("crs").at("horizontal_unit"), "metre");
    EXPECT_EQ(info.at("point_count"), j.at("points"));
    fs::remove_all(dir);
}

TEST(TerrainCommand, BadOptionsGiveOneLine) {
    std::string out;
    EXPECT_EQ(test::run_command(std::string(LIDARSCOUT_CLI) + " synth terrain -o /tmp/never --km 0 2>&1", out), 1);
    EXPECT_NE(out.find("size must be more than 0"), std::string::npos) << out;
    EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 1) << out;
    EXPECT_EQ(test::run_command(std::string(LIDARSCOUT_CLI) + " synth terrain -o /tmp/never --density -3 2>&1", out),
              1);
    EXPECT_NE(out.find("density"), std::string::npos) << out;
    EXPECT_FALSE(fs::exists("/tmp/never"));
    EXPECT_EQ(test::run_command(std::string(LIDARSCOUT_CLI) + " synth terrain --help", out), 0);
    EXPECT_NE(out.find("--density"), std::string::npos);
    EXPECT_NE(out.find("--seed"), std::string::npos);
}

}  // namespace
}  // namespace lidarscout
