// `synth replicate`: every output is a valid tile whose header, bounds and chunk points are the
// source's moved by the planned shift, whose decoded records equal the source's, and whose
// grid cell it does not leave; bad grids, missing sources and unsafe output folders are refused;
// a virtual replica (the manifest alone) opens as the same tiles as the copies.
#include <gtest/gtest.h>

#include <unistd.h>

#include <atomic>
#include <cmath>
#include <fstream>

#include "core/error.hpp"
#include "core/sha256.hpp"
#include "core/thread_pool.hpp"
#include "dataset/chunk_points.hpp"
#include "dataset/dataset.hpp"
#include "dataset/virtual_replica.hpp"
#include "dataset/point_reader.hpp"
#include "dataset/tile.hpp"
#include "io/file.hpp"
#include "las/copc.hpp"
#include "synth/replicate.hpp"
#include "test_data.hpp"

namespace lidarscout {
namespace {

namespace fs = std::filesystem;

// A fresh temporary folder, removed with everything in it at the end of the test.
struct TempDir {
    fs::path path;
    explicit TempDir(const std::string& name)
        : path(fs::temp_directory_path() / ("lidarscout_replicate_" + name + "_" + std::to_string(::getpid()))) {
        fs::remove_all(path);
        fs::create_directories(path);
    }
    ~TempDir() { fs::remove_all(path); }
};

const std::string kFeetTile = (test::surveys_dir() / "ky-red-river-gorge/N105E348.laz").string();
const std::string kMetreTile =
    (test::surveys_dir() / "ign-lidar-hd-1km/Semis_2022_0906_6665_LA93_IGN69_ok.laz").string();
const std::string kCopcTile = (test::formats_dir() / "PDAL__PDAL/test__data__copc__1.2-with-color.copc.laz").string();

std::string points_sha256(const std::string& path) {
    auto file = io::File::open(path);
    auto tile = dataset::read_tile(file);
    Sha256 sha;
    ThreadPool pool(2);
    dataset::for_each_record_batch(file, tile, pool,
                                   [&](std::uint64_t, std::span<const std::uint8_t> r) { sha.update(r); });
    return sha.hex_digest();
}

std::string cli(const std::string& args) {
    return std::string(LIDARSCOUT_CLI) + " synth replicate " + args + " 2>&1";
}

TEST(ReplicateGrid, ParsesNXxNY) {
    auto g = synth::parse_grid("45x45");
    EXPECT_EQ(g.nx, 45u);
    EXPECT_EQ(g.ny, 45u);
    g = synth::parse_grid("3X2");
    EXPECT_EQ(g.nx, 3u);
    EXPECT_EQ(g.ny, 2u);
    for (const char* bad : {"", "45", "x", "3x", "x3", "0x3", "3x0", "-1x2", "axb", "3x2x1", "1.5x2", "99999999x1"}) {
        EXPECT_THROW(synth::parse_grid(bad), Error) << bad;
    }
}

// The feet and metre tiles on a 3x2 grid: each output is checked against its source.
TEST(Replicate, OutputsAreShiftedCopiesOfTheirSources) {
    TempDir dir("grid");
    const auto plan = synth::plan_replicas({kFeetTile, kMetreTile}, dir.path.string(), {3, 2});
    ASSERT_EQ(plan.sources.size(), 2u);
    ASSERT_EQ(plan.tiles.size(), 6u);
    EXPECT_EQ(plan.sources[0].unit, "us_survey_foot");
    EXPECT_EQ(plan.sources[1].unit, "metre");
    const double step = std::pow(10.0, std::floor(std::log10(plan.cell_metres)) - 1);
    EXPECT_EQ(std::fmod(plan.cell_metres, step), 0.0) << plan.cell_metres << " m is a round number";
    EXPECT_GT(plan.cell_metres, std::max(plan.sources[0].footprint_metres, plan.sources[1].footprint_metres));
    ThreadPool pool(2);
    std::atomic<std::uint64_t> bytes{0};
    synth::write_replicas(plan, pool, [&](std::uint64_t n) { bytes += n; });
    EXPECT_EQ(bytes, plan.total_bytes);

    for (const auto& t : plan.tiles) {
        SCOPED_TRACE(t.path);
        EXPECT_EQ(t.source, (t.gx + t.gy * 3u) % 2u);
        const auto& src = plan.sources[t.source];
        auto src_file = io::File::open(src.path);
        auto file = io::File::open(t.path);
        const auto tile = dataset::read_tile(file);
        const auto& a = src.tile.header;
        const auto& b = tile.header;
        EXPECT_EQ(file.size(), src_file.size());
        EXPECT_EQ(b.point_count, a.point_count);
        for (int i = 0; i < 2; ++i) {
            EXPECT_EQ(t.shift[i], std::round(t.shift[i])) << "shift is a whole number of units";
            EXPECT_EQ(b.offset[i], a.offset[i] + t.shift[i]);
            EXPECT_EQ(b.min[i], a.min[i] + t.shift[i]);
            EXPECT_EQ(b.max[i], a.max[i] + t.shift[i]);
        }
        EXPECT_EQ(b.offset[2], a.offset[2]);
        EXPECT_EQ(b.min[2], a.min[2]);
        EXPECT_EQ(b.max[2], a.max[2]);
        EXPECT_EQ(tile.crs().epsg, src.tile.crs().epsg);

        const auto want = dataset::read_chunk_points(src_file, src.tile);
        const auto got = dataset::read_chunk_points(file, tile);
        ASSERT_EQ(got.size(), want.size());
        ASSERT_GT(got.size(), 0u);
        for (std::size_t i = 0; i < got.size(); ++i) {
            EXPECT_EQ(got[i].point.X, want[i].point.X);
            EXPECT_EQ(got[i].point.Y, want[i].point.Y);
            EXPECT_EQ(got[i].point.Z, want[i].point.Z);
            EXPECT_NEAR(got[i].point.x, want[i].point.x + t.shift[0], 1e-6);
            EXPECT_NEAR(got[i].point.y, want[i].point.y + t.shift[1], 1e-6);
            EXPECT_EQ(got[i].point.z, want[i].point.z);
        }
    }
    EXPECT_TRUE(fs::exists(dir.path / synth::kManifestName));
    const auto manifest = test::read_json(dir.path / synth::kManifestName);
    EXPECT_EQ(manifest.at("tiles").size(), 6u);
    EXPECT_EQ(manifest.at("total_points"), plan.total_points);
    EXPECT_EQ(plan.total_points,
              3 * (plan.sources[0].tile.header.point_count + plan.sources[1].tile.header.point_count));
}

// Each output stays inside its grid cell (in metres), so neighbours never overlap.
TEST(Replicate, CellsDoNotOverlap) {
    TempDir dir("cells");
    const auto plan = synth::plan_replicas({kFeetTile, kMetreTile}, dir.path.string(), {3, 2});
    struct Box { double x0, y0, x1, y1; };
    std::vector<Box> boxes;
    for (const auto& t : plan.tiles) {
        const auto& s = plan.sources[t.source];
        const auto& h = s.tile.header;
        Box b{(h.min[0] + t.shift[0]) * s.to_metres, (h.min[1] + t.shift[1]) * s.to_metres,
              (h.max[0] + t.shift[0]) * s.to_metres, (h.max[1] + t.shift[1]) * s.to_metres};
        const double cx = plan.anchor_metres[0] + t.gx * plan.cell_metres;
        const double cy = plan.anchor_metres[1] + t.gy * plan.cell_metres;
        EXPECT_GE(b.x0, cx - 1e-6);
        EXPECT_GE(b.y0, cy - 1e-6);
        EXPECT_LT(b.x1, cx + plan.cell_metres);
        EXPECT_LT(b.y1, cy + plan.cell_metres);
        boxes.push_back(b);
    }
    for (std::size_t i = 0; i < boxes.size(); ++i) {
        for (std::size_t j = i + 1; j < boxes.size(); ++j) {
            const auto& a = boxes[i];
            const auto& b = boxes[j];
            EXPECT_TRUE(a.x1 < b.x0 || b.x1 < a.x0 || a.y1 < b.y0 || b.y1 < a.y0) << i << " overlaps " << j;
        }
    }
    // The first tile stays where the first source is.
    EXPECT_EQ(plan.tiles[0].shift[0], 0.0);
    EXPECT_EQ(plan.tiles[0].shift[1], 0.0);
    EXPECT_FALSE(fs::exists(dir.path / synth::kManifestName)) << "planning writes nothing";
}

// Full decode with the LAZ codec: the records are the source's, byte for byte.
TEST(Replicate, ReplicaDecodesToTheSourceRecords) {
    TempDir dir("decode");
    const auto plan = synth::plan_replicas({kFeetTile}, dir.path.string(), {2, 1});
    ThreadPool pool(2);
    synth::write_replicas(plan, pool);
    ASSERT_NE(plan.tiles[1].shift[0], 0.0);
    EXPECT_EQ(points_sha256(plan.tiles[1].path), points_sha256(kFeetTile));
}

// A COPC copy keeps a valid hierarchy and its octree centre moves with the points.
TEST(Replicate, CopcCentreMovesWithThePoints) {
    TempDir dir("copc");
    const auto plan = synth::plan_replicas({kCopcTile}, dir.path.string(), {1, 2});
    ThreadPool pool(1);
    synth::write_replicas(plan, pool);
    const auto& t = plan.tiles[1];
    ASSERT_NE(t.shift[1], 0.0);
    auto file = io::File::open(t.path);
    const auto tile = dataset::read_tile(file);
    const auto& src = plan.sources[0].tile;
    ASSERT_TRUE(tile.copc && src.copc);
    EXPECT_EQ(tile.copc->center[0], src.copc->center[0] + t.shift[0]);
    EXPECT_EQ(tile.copc->center[1], src.copc->center[1] + t.shift[1]);
    EXPECT_EQ(tile.copc->center[2], src.copc->center[2]);
    EXPECT_EQ(las::read_copc_hierarchy(file, *tile.copc).total_points, tile.header.point_count);
    EXPECT_EQ(points_sha256(t.path), points_sha256(kCopcTile));
}

// A virtual replica (only the manifest) opens as the same tiles as the copies of the same plan:
// headers, bounds in metres, COPC centres and chunk points alike, and the same points decoded.
TEST(Replicate, VirtualReplicaOpensAsTheCopiedOne) {
    TempDir dir("virtual");
    const auto copied = synth::plan_replicas({kFeetTile, kCopcTile}, (dir.path / "copied").string(), {2, 2});
    const auto virt = synth::plan_replicas({kFeetTile, kCopcTile}, (dir.path / "virtual").string(), {2, 2});
    ThreadPool pool(2);
    synth::write_replicas(copied, pool);
    synth::write_virtual_replica(virt);
    const auto manifest = (dir.path / "virtual" / synth::kManifestName).string();
    EXPECT_EQ(fs::directory_iterator(dir.path / "virtual")->path().filename(), synth::kManifestName)
        << "copied nothing";
    ASSERT_TRUE(dataset::is_virtual_replica(manifest));
    EXPECT_FALSE(dataset::is_virtual_replica((dir.path / "copied" / synth::kManifestName).string()));

    std::vector<std::string> copies;
    for (const auto& t : copied.tiles) copies.push_back(t.path);
    const auto a = dataset::open_dataset(copies), b = dataset::open_dataset({manifest});
    ASSERT_TRUE(b.skipped.empty()) << b.skipped.front().error;
    ASSERT_EQ(a.tiles.size(), 4u);
    ASSERT_EQ(b.tiles.size(), 4u);
    EXPECT_EQ(b.point_count, a.point_count);
    EXPECT_EQ(b.chunk_point_count, a.chunk_point_count);
    for (std::size_t i = 0; i < 4; ++i) {  // both in plan order
        SCOPED_TRACE(copied.tiles[i].path);
        const auto &ha = a.tiles[i].tile.header, &hb = b.tiles[i].tile.header;
        EXPECT_EQ(hb.offset, ha.offset);
        EXPECT_EQ(hb.min, ha.min);
        EXPECT_EQ(hb.max, ha.max);
        EXPECT_EQ(b.tiles[i].bounds_m.min_x, a.tiles[i].bounds_m.min_x);
        EXPECT_EQ(b.tiles[i].bounds_m.max_y, a.tiles[i].bounds_m.max_y);
        EXPECT_EQ(b.tiles[i].tile.path(), virt.sources[virt.tiles[i].source].path) << "a virtual tile reads its source";
        ASSERT_EQ(a.tiles[i].tile.copc.has_value(), b.tiles[i].tile.copc.has_value());
        if (a.tiles[i].tile.copc) EXPECT_EQ(b.tiles[i].tile.copc->center[0], a.tiles[i].tile.copc->center[0]);
        const auto want = dataset::read_chunk_points(io::File::open(a.tiles[i].tile.path()), a.tiles[i].tile);
        const auto got = dataset::read_chunk_points(io::File::open(b.tiles[i].tile.path()), b.tiles[i].tile);
        ASSERT_EQ(got.size(), want.size());
        for (std::size_t k = 0; k < got.size(); k += 7) {
            EXPECT_EQ(got[k].point.x, want[k].point.x);
            EXPECT_EQ(got[k].point.y, want[k].point.y);
            EXPECT_EQ(got[k].point.z, want[k].point.z);
        }
    }
}

// A manifest that is broken is one skipped entry naming it; the other paths still open.
TEST(Replicate, BrokenVirtualManifestIsSkippedWithItsName) {
    TempDir dir("virtual_bad");
    const auto plan = synth::plan_replicas({kFeetTile}, dir.path.string(), {2, 1});
    synth::write_virtual_replica(plan);
    const auto manifest = dir.path / synth::kManifestName;
    auto json = test::read_json(manifest);
    json["tiles"][1]["source"] = 7;  // no such source
    {
        std::ofstream out(manifest);
        out << json.dump(1);
    }
    ASSERT_TRUE(dataset::is_virtual_replica(manifest.string()));
    const auto ds = dataset::open_dataset({manifest.string(), kMetreTile});
    ASSERT_EQ(ds.skipped.size(), 1u);
    EXPECT_EQ(ds.skipped[0].path, manifest.string());
    EXPECT_NE(ds.skipped[0].error.find("source"), std::string::npos) << ds.skipped[0].error;
    EXPECT_EQ(ds.tiles.size(), 1u);
}

TEST(Replicate, RefusesUnsafeOrEmptyInput) {
    TempDir dir("refuse");
    fs::copy_file(kMetreTile, dir.path / "a.laz");
    const auto src = (dir.path / "a.laz").string();
    EXPECT_THROW(synth::plan_replicas({dir.path.string()}, dir.path.string(), {2, 2}), Error);
    EXPECT_THROW(synth::plan_replicas({src}, dir.path.string(), {2, 2}), Error);
    EXPECT_THROW(synth::plan_replicas({src}, (dir.path / "..").string() , {2, 2}), Error);
    EXPECT_THROW(synth::plan_replicas({(dir.path / "missing.laz").string()}, (dir.path / "out").string(), {2, 2}),
                 Error);
    EXPECT_THROW(synth::plan_replicas({src}, (dir.path / "out").string(), {0, 2}), Error);
    // Unreadable sources are skipped with a warning; none readable is an error.
    std::FILE* f = std::fopen((dir.path / "bad.laz").c_str(), "w");
    std::fputs("not a LAS file", f);
    std::fclose(f);
    EXPECT_THROW(synth::plan_replicas({(dir.path / "bad.laz").string()}, (dir.path / "out").string(), {2, 2}), Error);
    const auto plan = synth::plan_replicas({dir.path.string()}, (dir.path / "out").string(), {2, 2});
    EXPECT_EQ(plan.sources.size(), 1u);
    ASSERT_EQ(plan.warnings.size(), 1u);
    EXPECT_NE(plan.warnings[0].message.find("bad.laz"), std::string::npos);
    EXPECT_EQ(fs::file_size(src), fs::file_size(kMetreTile)) << "the source is untouched";
}

TEST(ReplicateCommand, WritesSummaryAndRejectsBadArguments) {
    TempDir dir("cli");
    std::string out;
    const auto outdir = (dir.path / "out").string();
    ASSERT_EQ(test::run_command(cli(kMetreTile + " -o " + outdir + " --grid 2x1 --json --threads 2"), out), 0) << out;
    auto j = nlohmann::json::parse(out);
    EXPECT_EQ(j.at("tiles"), 2);
    EXPECT_EQ(j.at("points"), 2 * dataset::read_tile(io::File::open(kMetreTile)).header.point_count);
    EXPECT_EQ(j.at("bytes"), 2 * fs::file_size(kMetreTile));
    ASSERT_EQ(test::run_command(std::string(LIDARSCOUT_CLI) + " info --json " + outdir + " 2>&1", out), 0) << out;

    EXPECT_EQ(test::run_command(cli(kMetreTile + " -o " + outdir + " --grid 45"), out), 1);
    EXPECT_NE(out.find("expected NXxNY"), std::string::npos) << out;
    EXPECT_EQ(out.find('\n'), out.size() - 1) << "one line: " << out;
    EXPECT_EQ(test::run_command(cli((dir.path / "nope.laz").string() + " -o " + outdir + " --grid 2x2"), out), 1);
    EXPECT_NE(out.find("no such file or folder"), std::string::npos) << out;
    EXPECT_EQ(test::run_command(cli(outdir + " -o " + outdir + " --grid 2x2"), out), 1);
    EXPECT_NE(out.find("refusing the output of -o/--output: it is the input"), std::string::npos) << out;
    EXPECT_EQ(test::run_command(std::string(LIDARSCOUT_CLI) + " synth replicate --help", out), 0);
    EXPECT_NE(out.find("not a data product"), std::string::npos) << out;
}

}  // namespace
}  // namespace lidarscout
