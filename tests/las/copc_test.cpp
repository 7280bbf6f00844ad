// COPC: the 11 COPC files of the format corpus (hierarchy vs header and vs the LAZ chunk
// table that LASzip reports), non-COPC files, and hand-made hostile hierarchies.
#include "las/copc.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <tuple>
#include <vector>

#include "core/error.hpp"
#include "io/file.hpp"
#include "las/header.hpp"
#include "las/vlr.hpp"
#include "test_data.hpp"

namespace lidarscout::las {
namespace {

namespace fs = std::filesystem;

const char* const kCopcFiles[] = {
    "IGNF__ctview/data__las__classee__test_data_77050_627755_LA93_IGN69.copc.laz",
    "PDAL__PDAL/test__data__copc__1.2-with-color.copc.laz",
    "PDAL__PDAL/test__data__copc__lone-star.copc.laz",
    "PDAL__PDAL/test__data__tindex__autzen_clip_4326.copc.laz",
    "PDAL__PDAL/test__data__tindex__autzen_clip_native.copc.laz",
    "gadomski__las-rs/tests__data__autzen.copc.laz",
    "hobuinc__silvimetric/tests__data__autzen_test.copc.laz",
    "laspy__laspy/tests__data__simple_with_page.copc.laz",
    "potree__potree/pointclouds__lion_takanawa.copc.laz",
    "r-lidar__lasR/inst__extdata__example.copc.laz",
    "visgl__loaders.gl/modules__copc__test__data__ellipsoid.copc.laz",
};

struct Opened {
    io::File file;
    Header header;
    std::vector<Vlr> vlrs;
};

Opened open(const fs::path& path) {
    Opened o{io::File::open(path.string()), {}, {}};
    o.header = read_header(o.file);
    o.vlrs = read_vlrs(o.file, o.header);
    return o;
}


using Range = std::tuple<std::uint64_t, std::uint64_t, std::uint64_t>;  // offset, bytes, points

TEST(Copc, CorpusHierarchiesMatchHeaderAndChunkTable) {
    std::size_t compared = 0;
    for (const char* name : kCopcFiles) {
        SCOPED_TRACE(name);
        const auto o = open(test::formats_dir() / name);
        const auto info = find_copc_info(o.vlrs, o.file.path());
        ASSERT_TRUE(info.has_value());
        EXPECT_GT(info->halfsize, 0.0);
        const CopcHierarchy h = read_copc_hierarchy(o.file, *info);
        EXPECT_GE(h.pages, 1u);
        ASSERT_FALSE(h.nodes.empty());
        EXPECT_EQ(h.total_points, o.header.point_count);

        std::multiset<Range> nodes;
        for (const auto& n : h.nodes) {
            EXPECT_GT(n.point_count, 0);
            EXPECT_GE(n.offset, o.header.offset_to_point_data);
            EXPECT_LE(n.offset + static_cast<std::uint64_t>(n.byte_size), o.file.size());
            nodes.insert(
                {n.offset, static_cast<std::uint64_t>(n.byte_size), static_cast<std::uint64_t>(n.point_count)});
        }

        const auto expected_path = test::formats_dir() / "expected" / (fs::path(name).parent_path().string() + "__" +
                                                                        fs::path(name).filename().string() + ".json");
        const auto json = test::read_json(expected_path);
        if (!json.contains("chunks")) continue;
        std::multiset<Range> chunks;
        for (const auto& c : json.at("chunks")) {
            chunks.insert({c.at("byte_offset").get<std::uint64_t>(), c.at("byte_size").get<std::uint64_t>(),
                           c.at("point_count").get<std::uint64_t>()});
        }
        EXPECT_EQ(nodes, chunks) << name;  // COPC nodes are exactly the LAZ chunks (tables as written)
        ++compared;
    }
    EXPECT_EQ(compared, 11u);  // every COPC file of the corpus with a chunk list
}

TEST(Copc, ChildPagesAreFollowed) {
    const auto o = open(test::formats_dir() / "laspy__laspy/tests__data__simple_with_page.copc.laz");
    const auto info = find_copc_info(o.vlrs, o.file.path());
    ASSERT_TRUE(info.has_value());
    const CopcHierarchy h = read_copc_hierarchy(o.file, *info);
    EXPECT_EQ(h.pages, 2u);
    EXPECT_EQ(h.nodes.size(), 65u);
    EXPECT_EQ(h.total_points, 1065u);
    EXPECT_EQ(h.nodes.front().level, 0);  // the root node comes first
}

TEST(Copc, OnlyTheCopcFilesOfTheCorpusAreDetected) {
    const std::set<std::string> copc(std::begin(kCopcFiles), std::end(kCopcFiles));
    std::size_t found = 0, plain = 0;
    for (const auto& e : test::all_expected()) {
        Opened o;
        try {
            o = open(e.file);
        } catch (const Error&) {
            continue;  // broken files are the header reader's business
        }
        const auto rel = fs::relative(e.file, test::formats_dir()).generic_string();
        const bool detected = find_copc_info(o.vlrs, o.file.path()).has_value();
        EXPECT_EQ(detected, copc.count(rel) > 0) << rel;
        (detected ? found : plain) += 1;
    }
    EXPECT_EQ(found, 11u);
    EXPECT_GT(plain, 100u);
}

// ---- Hostile hierarchies in hand-made files -----------------------------------------------

struct EntrySpec {
    std::int32_t level, x, y, z;
    std::uint64_t offset;
    std::int32_t byte_size, point_count;
};

class CopcHostile : public ::testing::Test {
protected:
    static constexpr std::uint64_t kFileSize = 4096;
    static constexpr std::uint64_t kPage = 1024;

    void SetUp() override {
        path_ = fs::temp_directory_path() /
                ("lidarscout_copc_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
                 ::testing::UnitTest::GetInstance()->current_test_info()->name() + ".bin");
        bytes_.assign(kFileSize, 0);
    }
    void TearDown() override { fs::remove(path_); }

    void put(std::uint64_t at, const std::vector<EntrySpec>& entries) {
        for (const auto& e : entries) {
            std::memcpy(&bytes_[at + 0], &e.level, 4);
            std::memcpy(&bytes_[at + 4], &e.x, 4);
            std::memcpy(&bytes_[at + 8], &e.y, 4);
            std::memcpy(&bytes_[at + 12], &e.z, 4);
            std::memcpy(&bytes_[at + 16], &e.offset, 8);
            std::memcpy(&bytes_[at + 24], &e.byte_size, 4);
            std::memcpy(&bytes_[at + 28], &e.point_count, 4);
            at += 32;
        }
    }
    CopcHierarchy read(std::uint64_t root_offset, std::uint64_t root_size) {
        std::ofstream(path_, std::ios::binary).write(reinterpret_cast<const char*>(bytes_.data()), bytes_.size());
        auto file = io::File::open(path_.string());
        CopcInfo info;
        info.root_hier_offset = root_offset;
        info.root_hier_size = root_size;
        return read_copc_hierarchy(file, info);
    }
    // The Error thrown by read(), or a failure if none is.
    Error read_error(std::uint64_t root_offset, std::uint64_t root_size) {
        try {
            read(root_offset, root_size);
        } catch (const Error& e) {
            EXPECT_EQ(e.file(), path_.string());
            EXPECT_TRUE(e.offset().has_value());
            return e;
        }
        ADD_FAILURE() << "no error thrown";
        return Error("none");
    }

    fs::path path_;
    std::vector<std::uint8_t> bytes_;
};

TEST_F(CopcHostile, ValidTwoPageHierarchy) {
    put(kPage, {{0, 0, 0, 0, 500, 100, 10}, {1, 1, 0, 1, 2048, 64, -1}, {1, 0, 0, 0, 0, 0, 0}});
    put(2048, {{1, 1, 0, 1, 600, 50, 7}, {2, 3, 1, 2, 700, 60, 5}});
    const auto h = read(kPage, 96);
    EXPECT_EQ(h.pages, 2u);
    ASSERT_EQ(h.nodes.size(), 3u);
    EXPECT_EQ(h.total_points, 22u);
    EXPECT_EQ(h.nodes[2].level, 2);
    EXPECT_EQ(h.nodes[2].offset, 700u);
}

TEST_F(CopcHostile, CycleIsRejected) {
    put(kPage, {{0, 0, 0, 0, 500, 100, 10}, {1, 0, 0, 0, kPage, 64, -1}});  // points back to itself
    const Error e = read_error(kPage, 64);
    EXPECT_NE(e.cause().find("cycle"), std::string::npos) << e.what();
    EXPECT_EQ(e.offset(), kPage + 32);  // the entry that closes the cycle
}

TEST_F(CopcHostile, PageOutsideTheFileIsRejected) {
    EXPECT_NE(read_error(kFileSize - 32, 64).cause().find("outside the file"), std::string::npos);
    EXPECT_NE(read_error(~std::uint64_t{0} - 16, 32).cause().find("outside the file"), std::string::npos);
    put(kPage, {{1, 0, 0, 0, 1u << 20, 32, -1}});
    EXPECT_NE(read_error(kPage, 32).cause().find("outside the file"), std::string::npos);
}

TEST_F(CopcHostile, PageSizeMustBeAPositiveMultipleOf32) {
    EXPECT_NE(read_error(kPage, 40).cause().find("multiple of 32"), std::string::npos);
    EXPECT_NE(read_error(kPage, 0).cause().find("multiple of 32"), std::string::npos);
    put(kPage, {{1, 0, 0, 0, 2048, -32, -1}});
    EXPECT_NE(read_error(kPage, 32).cause().find("child page of size -32"), std::string::npos);
}

TEST_F(CopcHostile, NodeDataOutsideTheFileIsRejected) {
    put(kPage, {{0, 0, 0, 0, kFileSize - 10, 100, 10}});
    const Error e = read_error(kPage, 32);
    EXPECT_NE(e.cause().find("outside the file"), std::string::npos) << e.what();
    EXPECT_EQ(e.offset(), kPage);
}

TEST_F(CopcHostile, BadEntriesAreRejected) {
    put(kPage, {{0, 0, 0, 0, 500, 100, -2}});
    EXPECT_NE(read_error(kPage, 32).cause().find("point count -2"), std::string::npos);
    put(kPage, {{-1, 0, 0, 0, 500, 100, 10}});
    EXPECT_NE(read_error(kPage, 32).cause().find("invalid key -1-0-0-0"), std::string::npos);
    put(kPage, {{2, 4, 0, 0, 500, 100, 10}});  // x must be < 2^level
    EXPECT_NE(read_error(kPage, 32).cause().find("invalid key 2-4-0-0"), std::string::npos);
    put(kPage, {{0, 0, 0, 0, 500, 0, 10}});  // points but no bytes
    EXPECT_NE(read_error(kPage, 32).cause().find("empty or lies outside"), std::string::npos);
}

TEST_F(CopcHostile, TooManyEntriesForTheFileSize) {
    // A chain of overlapping pages, each 3 KiB long and starting 32 bytes after the previous
    // one: no page repeats, but together they list far more entries than 4 KiB can hold.
    for (std::uint64_t at = 0; at + 3072 <= kFileSize; at += 32) {
        const std::uint64_t next = at + 32;
        put(at, {{0, 0, 0, 0, next, 3072, next + 3072 <= kFileSize ? -1 : 0}});
    }
    const Error e = read_error(0, 3072);
    EXPECT_NE(e.cause().find("more than 128 entries"), std::string::npos) << e.what();
}

TEST(Copc, InfoVlrMustBeFirstAndComplete) {
    Vlr laszip;
    laszip.user_id = "laszip encoded";
    laszip.record_id = 22204;
    Vlr info;
    info.user_id = "copc";
    info.record_id = 1;
    info.data_offset = 429;
    info.data.assign(160, 0);
    info.data_size = 160;
    info.data_loaded = true;
    const double halfsize = 12.5;
    std::memcpy(&info.data[24], &halfsize, 8);
    const std::uint64_t root = 4242;
    std::memcpy(&info.data[40], &root, 8);

    auto found = find_copc_info({info, laszip}, "x.copc.laz");
    ASSERT_TRUE(found.has_value());
    EXPECT_EQ(found->halfsize, 12.5);
    EXPECT_EQ(found->root_hier_offset, 4242u);
    EXPECT_FALSE(find_copc_info({laszip, info}, "x.copc.laz").has_value());  // not first: not COPC
    EXPECT_FALSE(find_copc_info({}, "x.copc.laz").has_value());

    info.data.resize(100);
    info.data_size = 100;
    try {
        find_copc_info({info}, "x.copc.laz");
        ADD_FAILURE() << "no error thrown";
    } catch (const Error& e) {
        EXPECT_EQ(e.file(), "x.copc.laz");
        EXPECT_EQ(e.offset(), 429u);
    }
}

}  // namespace
}  // namespace lidarscout::las
