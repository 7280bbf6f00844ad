// The LAZ chunk table: every chunked file of the reference set gives LASzip's chunks exactly;
// point-wise files have none; and hand-damaged copies of real files (table at the end, moved,
// truncated, garbage counts, header counts that disagree) are read or rejected as documented
// in chunk_table.hpp; the table keeps 8 bytes a chunk (16 for variable-size chunks).
#include <gtest/gtest.h>

#include <unistd.h>

#include <cctype>
#include <cstring>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "io/file.hpp"
#include "las/header.hpp"
#include "las/laszip_vlr.hpp"
#include "las/vlr.hpp"
#include "laz/laz.hpp"
#include "laz/integer_models.hpp"
#include "laz/test_arithmetic_encoder.hpp"
#include "allocation_counter.hpp"
#include "test_data.hpp"

namespace lidarscout::laz {
namespace {

using lidarscout::test::Expected;
namespace fs = std::filesystem;

ChunkTable table_of(const fs::path& path) {
    auto file = io::File::open(path.string());
    const auto header = las::read_header(file);
    const auto vlrs = las::read_vlrs(file, header);
    const las::Vlr* v = las::find_vlr(vlrs, "laszip encoded", 22204);
    if (!v) throw Error(path.string(), std::nullopt, "test: no laszip VLR");
    const auto laz = las::parse_laszip_vlr(v->data, file.path(), v->data_offset);
    return read_chunk_table(file, header, laz);
}

// The cause of the Error reading the table throws, or "" when it reads fine.
std::string rejection(const fs::path& path) {
    try {
        table_of(path);
    } catch (const Error& e) {
        EXPECT_EQ(e.file(), path.string());
        return e.cause();
    }
    return "";
}

std::vector<Chunk> chunks_in(const nlohmann::json& list) {
    std::vector<Chunk> out;
    for (const auto& c : list) {
        out.push_back({c.at("first_point").get<std::uint64_t>(), c.at("point_count").get<std::uint64_t>(),
                       c.at("byte_offset").get<std::uint64_t>(), c.at("byte_size").get<std::uint64_t>()});
    }
    return out;
}

std::string describe(const std::vector<Chunk>& chunks) {
    std::string s;
    for (const auto& c : chunks) {
        std::ostringstream one;
        one << '{' << c.first_point << ", " << c.point_count << ", " << c.byte_offset << ", " << c.byte_size << "} ";
        s += one.str();
    }
    return s;
}

// ---- the reference set ------------------------------------------------------------------------

// lasR's example.copc.laz has chunk_size 0 (neither fixed nor the variable marker) while its
// table is written as a variable one: 30 points in 418 bytes, as its COPC hierarchy also says.
// The reference JSON lists the table as written (its `chunks_note`).
const std::vector<Chunk> kChunkSizeZeroChunks = {{0, 30, 1449, 418}};

std::vector<Expected> files_with_chunk_lists() {
    std::vector<Expected> out;
    for (auto& e : lidarscout::test::all_expected()) {
        if (e.json->contains("chunks") && e.json->at("reference_result") == "decodes") out.push_back(std::move(e));
    }
    return out;
}

std::string readable(const ::testing::TestParamInfo<Expected>& info) {
    std::string s = info.param.name;
    for (char& c : s) if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
    return s;
}

class ChunkTableMatchesReference : public ::testing::TestWithParam<Expected> {};

TEST_P(ChunkTableMatchesReference, SameChunksAsLaszip) {
    const auto& e = GetParam();
    const auto expected = chunks_in(e.json->at("chunks"));
    const auto table = table_of(e.file);
    const auto chunks = table.chunks();
    EXPECT_EQ(chunks, expected) << "got      " << describe(chunks) << "\nexpected " << describe(expected);
    EXPECT_EQ(table.size(), expected.size());
    for (std::size_t i = 0; i < table.size() && i < expected.size(); ++i) EXPECT_EQ(table[i], expected[i]) << i;
    EXPECT_FALSE(table.offset_from_file_end);
    if (e.json->at("laz").at("compressor") == 1) {
        EXPECT_EQ(table.table_offset, 0u);  // point-wise: no table at all
    } else if (!table.chunks().empty()) {
        EXPECT_EQ(table.table_offset, table.chunks().back().byte_offset + table.chunks().back().byte_size);
    }
}

INSTANTIATE_TEST_SUITE_P(Formats, ChunkTableMatchesReference, ::testing::ValuesIn(files_with_chunk_lists()), readable);

TEST(ChunkTableFormats, ReferenceCoversAllChunkedFiles) {
    const auto files = files_with_chunk_lists();
    EXPECT_EQ(files.size(), 74u);
    std::size_t chunked = 0, pointwise = 0;
    for (const auto& e : files) {
        chunked += !e.json->at("chunks").empty();
        pointwise += e.json->at("laz").at("compressor") == 1;
    }
    EXPECT_EQ(chunked, 70u);
    EXPECT_EQ(pointwise, 3u);
}

TEST(ChunkTableFormats, ChunkSizeZeroMeansVariableChunks) {
    const auto path = lidarscout::test::formats_dir() / "r-lidar__lasR/inst__extdata__example.copc.laz";
    EXPECT_EQ(table_of(path).chunks(), kChunkSizeZeroChunks);
    las::LaszipVlr laz;
    laz.chunk_size = 0;
    EXPECT_TRUE(has_variable_chunks(laz));
    laz.chunk_size = las::LaszipVlr::kVariableChunkSize;
    EXPECT_TRUE(has_variable_chunks(laz));
    laz.chunk_size = 50000;
    EXPECT_FALSE(has_variable_chunks(laz));
}

// ---- damaged copies of real files -------------------------------------------------------------

// autzen_trim.laz: LAS 1.2, fixed chunks of 50,000; 110,000 points in 3 chunks.
constexpr const char* kAutzen = "PDAL__PDAL/test__data__laz__autzen_trim.laz";
constexpr std::uint64_t kAutzenPosition = 2144;  // offset_to_point_data
constexpr std::uint64_t kAutzenTable = 603333;
constexpr std::uint64_t kLegacyCountField = 107;
constexpr std::uint64_t kAutzenChunkSizeField = 2104;  // in the laszip VLR payload (at 2092)
// lone-star.copc.laz: LAS 1.4, variable chunks; 518,862 points in 15 chunks.
constexpr const char* kLoneStar = "PDAL__PDAL/test__data__copc__lone-star.copc.laz";
constexpr std::uint64_t kExtendedCountField = 247;
constexpr std::uint64_t kLoneStarPoints = 518862;

template <typename T>
void poke(std::vector<std::uint8_t>& bytes, std::uint64_t at, T value) {
    std::memcpy(bytes.data() + at, &value, sizeof(T));
}

// A copy of a data file, edited, deleted when the test ends.
class EditedFile {
public:
    EditedFile(const char* name, const std::function<void(std::vector<std::uint8_t>&)>& edit) {
        std::ifstream in(lidarscout::test::formats_dir() / name, std::ios::binary);
        std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), {});
        edit(bytes);
        std::string name_part = std::to_string(::getpid());
        name_part += '_';
        name_part += ::testing::UnitTest::GetInstance()->current_test_info()->name();
        path_ = fs::temp_directory_path() / ("lidarscout_chunk_table_" + name_part + ".laz");
        std::ofstream out(path_, std::ios::binary);
        out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    }
    ~EditedFile() { fs::remove(path_); }
    const fs::path& path() const { return path_; }

private:
    fs::path path_;
};

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

TEST(ChunkTableDamaged, UnchangedCopyReadsFine) {
    EditedFile f(kAutzen, [](auto&) {});
    const auto t = table_of(f.path());
    ASSERT_EQ(t.chunks().size(), 3u);
    EXPECT_EQ(t.table_offset, kAutzenTable);
    EXPECT_EQ(t.chunks()[2], (Chunk{100000, 10000, 548074, 55259}));
}

TEST(ChunkTableDamaged, PositionMinusOneIsReadFromTheFileEnd) {
    EditedFile f(kAutzen, [](auto& b) {
        poke<std::int64_t>(b, kAutzenPosition, -1);
        b.resize(b.size() + 8);
        poke<std::int64_t>(b, b.size() - 8, kAutzenTable);
    });
    const auto t = table_of(f.path());
    EXPECT_TRUE(t.offset_from_file_end);
    EXPECT_EQ(t.table_offset, kAutzenTable);
    EXPECT_EQ(t.chunks(), table_of(lidarscout::test::formats_dir() / kAutzen).chunks());
}

TEST(ChunkTableDamaged, PositionMinusOneWithGarbageAtTheEnd) {
    EditedFile f(kAutzen, [](auto& b) {
        poke<std::int64_t>(b, kAutzenPosition, -1);
        b.resize(b.size() + 8);
        poke<std::int64_t>(b, b.size() - 8, -1);
    });
    EXPECT_TRUE(contains(rejection(f.path()), "position -1 lies outside"));
}

TEST(ChunkTableDamaged, PositionPointingAtItselfMeansNoTable) {
    EditedFile f(kAutzen, [](auto& b) { poke<std::int64_t>(b, kAutzenPosition, kAutzenPosition); });
    EXPECT_TRUE(contains(rejection(f.path()), "writer was interrupted"));
}

TEST(ChunkTableDamaged, PositionBeyondTheFile) {
    EditedFile f(kAutzen, [](auto& b) { poke<std::int64_t>(b, kAutzenPosition, b.size() - 4); });
    EXPECT_TRUE(contains(rejection(f.path()), "lies outside"));
}

TEST(ChunkTableDamaged, PositionBeforeTheChunks) {
    EditedFile f(kAutzen, [](auto& b) { poke<std::int64_t>(b, kAutzenPosition, 100); });
    EXPECT_TRUE(contains(rejection(f.path()), "position 100 lies outside 2152"));
}

TEST(ChunkTableDamaged, FileEndsBeforeThePosition) {
    EditedFile f(kAutzen, [](auto& b) { b.resize(kAutzenPosition + 4); });
    EXPECT_TRUE(contains(rejection(f.path()), "ends before the 8-byte chunk table position"));
}

TEST(ChunkTableDamaged, UnknownVersion) {
    EditedFile f(kAutzen, [](auto& b) { poke<std::uint32_t>(b, kAutzenTable, 1); });
    EXPECT_TRUE(contains(rejection(f.path()), "unknown version 1"));
}

TEST(ChunkTableDamaged, GarbageChunkCountIsCaughtBeforeAnyAllocation) {
    EditedFile f(kAutzen, [](auto& b) { poke<std::uint32_t>(b, kAutzenTable + 4, 0xFFFFFFFFu); });
    EXPECT_TRUE(contains(rejection(f.path()), "announces 4294967295 chunks but only 601181 bytes"));
}

TEST(ChunkTableDamaged, LargeButPossibleCountFailsOnTheEntries) {
    // 500,000 chunks fit in 601,181 bytes, but the coded bytes end after 3 entries.
    EditedFile f(kAutzen, [](auto& b) { poke<std::uint32_t>(b, kAutzenTable + 4, 500000u); });
    const auto why = rejection(f.path());
    EXPECT_TRUE(contains(why, "truncated") || contains(why, "runs past the table") || contains(why, "size of 0 bytes"))
        << why;
}

TEST(ChunkTableDamaged, GarbageEntriesNeverEscapeTheChecks) {
    // Random bytes in place of the coded entries: either an Error, or chunks that respect
    // every documented invariant.
    for (std::uint32_t seed = 1; seed <= 50; ++seed) {
        EditedFile f(kAutzen, [seed](auto& b) {
            std::uint32_t x = seed * 2654435761u;
            for (std::uint64_t i = kAutzenTable + 8; i < b.size(); ++i) {
                x = x * 1664525u + 1013904223u;
                b[i] = static_cast<std::uint8_t>(x >> 24);
            }
        });
        try {
            const auto t = table_of(f.path());
            ASSERT_EQ(t.chunks().size(), 3u) << seed;
            std::uint64_t end = kAutzenPosition + 8;
            for (const auto& c : t.chunks()) {
                EXPECT_EQ(c.byte_offset, end);
                EXPECT_GT(c.byte_size, 0u);
                end += c.byte_size;
            }
            EXPECT_LE(end, kAutzenTable) << seed;
        } catch (const Error& e) {
            EXPECT_EQ(e.file(), f.path().string());
            EXPECT_EQ(e.offset(), kAutzenTable) << e.what();
        }
    }
}

TEST(ChunkTableDamaged, TruncatedEntries) {
    EditedFile f(kAutzen, [](auto& b) { b.resize(kAutzenTable + 8 + 4); });
    EXPECT_TRUE(contains(rejection(f.path()), "truncated: entry"));
}

TEST(ChunkTableDamaged, MissingTrailingZerosAreHarmless) {
    EditedFile f(kAutzen, [](auto& b) { b.resize(b.size() - 3); });  // the writer's 3 zero bytes
    EXPECT_EQ(table_of(f.path()).chunks(), table_of(lidarscout::test::formats_dir() / kAutzen).chunks());
}

TEST(ChunkTableDamaged, ChunkRunningIntoTheTable) {
    // The same table copied into the middle of the second chunk: that chunk overruns it.
    EditedFile f(kAutzen, [](auto& b) {
        std::memcpy(b.data() + 300000, b.data() + kAutzenTable, 20);
        poke<std::int64_t>(b, kAutzenPosition, 300000);
    });
    EXPECT_TRUE(
        contains(rejection(f.path()), "chunk 1 at byte 285651 with 262423 bytes runs past the table at 300000"));
}

TEST(ChunkTableDamaged, NoChunksForSomePoints) {
    EditedFile f(kAutzen, [](auto& b) { poke<std::uint32_t>(b, kAutzenTable + 4, 0); });
    EXPECT_TRUE(contains(rejection(f.path()), "its 0 chunks hold 0 points but the header announces 110000"));
}

TEST(ChunkTableDamaged, FixedChunksCutAtTheHeaderCount) {
    EditedFile f(kAutzen, [](auto& b) { poke<std::uint32_t>(b, kLegacyCountField, 60000); });
    const auto t = table_of(f.path());
    EXPECT_EQ(t.chunks(), (std::vector<Chunk>{{0, 50000, 2152, 283499}, {50000, 10000, 285651, 262423}}));
}

TEST(ChunkTableDamaged, FixedChunksShortOfTheHeaderCount) {
    EditedFile f(kAutzen, [](auto& b) { poke<std::uint32_t>(b, kLegacyCountField, 150001); });
    const auto why = rejection(f.path());
    EXPECT_TRUE(contains(why, "its 3 chunks hold 150000 points but the header announces 150001")) << why;
    EXPECT_TRUE(contains(why, "cannot be located without decoding")) << why;
}

TEST(ChunkTableDamaged, VariableChunksCutAtTheHeaderCount) {
    EditedFile f(kLoneStar, [](auto& b) { poke<std::uint64_t>(b, kExtendedCountField, kLoneStarPoints - 1); });
    const auto t = table_of(f.path());
    ASSERT_EQ(t.chunks().size(), 15u);
    EXPECT_EQ(t.chunks().back().point_count, 33646u);
    EXPECT_EQ(t.chunks().back().first_point + t.chunks().back().point_count, kLoneStarPoints - 1);
}

TEST(ChunkTableDamaged, VariableChunksDroppedPastTheHeaderCount) {
    EditedFile f(kLoneStar, [](auto& b) { poke<std::uint64_t>(b, kExtendedCountField, 212 + 100); });
    const auto t = table_of(f.path());
    EXPECT_EQ(t.chunks().size(), 2u);
    EXPECT_EQ(t.chunks()[1].point_count, 100u);
}

TEST(ChunkTableDamaged, VariableChunksShortOfTheHeaderCount) {
    EditedFile f(kLoneStar, [](auto& b) { poke<std::uint64_t>(b, kExtendedCountField, kLoneStarPoints + 1); });
    EXPECT_TRUE(contains(rejection(f.path()), "its 15 chunks hold 518862 points but the header announces 518863"));
}

TEST(ChunkTableDamaged, EntriesStopAtTheEvlrs) {
    // One chunk more than coded: the 16th entry would have to come from the EVLR that
    // follows the table.
    EditedFile f(kLoneStar, [](auto& b) { poke<std::uint32_t>(b, 2704562 + 4, 16); });
    EXPECT_TRUE(
        contains(rejection(f.path()), "truncated: entry 15 of 16 runs past the end of the table's bytes at 2704653"));
}

// ---- tables written by the test encoder ---------------------------------------------------------

struct Entry {
    std::uint32_t points, bytes;
};

// The table bytes (version, count, coded entries) for `entries`.
std::vector<std::uint8_t> encode_table(const std::vector<Entry>& entries, bool variable) {
    std::vector<std::uint8_t> out(8, 0);
    poke<std::uint32_t>(out, 4, static_cast<std::uint32_t>(entries.size()));
    test::TestEncoder enc;
    IntegerModels models(32, 2, 8, 0);
    Entry previous{0, 0};
    for (const auto& e : entries) {
        auto as_int = [](std::uint32_t v) { return static_cast<std::int32_t>(v); };
        if (variable) test::encode_integer(enc, models, as_int(previous.points), as_int(e.points), 0);
        test::encode_integer(enc, models, as_int(previous.bytes), as_int(e.bytes), 1);
        previous = e;
    }
    const auto coded = enc.finish();
    out.insert(out.end(), coded.begin(), coded.end());
    return out;
}

// autzen_trim.laz with its table replaced by `entries` (and variable chunks if asked).
void replace_autzen_table(std::vector<std::uint8_t>& b, const std::vector<Entry>& entries, bool variable) {
    if (variable) poke<std::uint32_t>(b, kAutzenChunkSizeField, las::LaszipVlr::kVariableChunkSize);
    b.resize(kAutzenTable);
    const auto table = encode_table(entries, variable);
    b.insert(b.end(), table.begin(), table.end());
}

// ---- hostile headers: what a header claims never sets how much we allocate or loop --------

// Reads `path` as the dataset layer does (header, VLRs, chunk table); returns the bytes it
// allocated and the error's text (empty when it read). The claims below are absurd for a file of
// well under a megabyte, so reading must fail (or succeed) without allocating for the claim.
std::pair<std::size_t, std::string> read_counted(const fs::path& path) {
    const lidarscout::test::AllocationCounter counter;
    std::string error;
    try {
        (void)table_of(path);
    } catch (const Error& e) {
        error = e.what();
    }
    return {counter.bytes(), error};
}

// What reading one of these small files may allocate in all (it allocates about its own size).
constexpr std::size_t kBoundedBytes = 32u << 20;

TEST(ChunkTableHostile, TrillionPointHeaderIsRejectedAtOnce) {
    EditedFile f(kLoneStar, [](auto& b) { poke<std::uint64_t>(b, kExtendedCountField, 1'000'000'000'000ull); });
    const auto [bytes, error] = read_counted(f.path());
    EXPECT_LT(bytes, kBoundedBytes);
    EXPECT_FALSE(error.empty());
    EXPECT_TRUE(contains(error, f.path().string())) << error;
}

TEST(ChunkTableHostile, MillionsOfChunksClaimedInASmallFile) {
    EditedFile f(kAutzen, [](auto& b) { poke<std::uint32_t>(b, kAutzenTable + 4, 50'000'000u); });
    const auto [bytes, error] = read_counted(f.path());
    EXPECT_LT(bytes, kBoundedBytes);
    EXPECT_FALSE(error.empty()) << "50 M chunks in a 600 KB file were accepted";
}

// A VLR count beyond what fits before the point data is read as far as it fits (a warning in
// the tile), in time proportional to the file, not to the claim.
TEST(ChunkTableHostile, BillionsOfVlrsClaimedInASmallFile) {
    constexpr std::uint64_t kVlrCountField = 100;
    EditedFile f(kAutzen, [](auto& b) { poke<std::uint32_t>(b, kVlrCountField, 4'000'000'000u); });
    const auto [bytes, error] = read_counted(f.path());
    EXPECT_LT(bytes, kBoundedBytes);
    EXPECT_TRUE(error.empty()) << error;
    auto file = io::File::open(f.path().string());
    const auto header = las::read_header(file);
    EXPECT_EQ(header.number_of_vlrs, 4'000'000'000u);
    EXPECT_LE(las::read_vlrs(file, header).size(), 6u);
}

TEST(ChunkTableWritten, TestEncoderReproducesLaszipsTable) {
    std::ifstream in(lidarscout::test::formats_dir() / kAutzen, std::ios::binary);
    std::vector<std::uint8_t> file((std::istreambuf_iterator<char>(in)), {});
    const std::vector<std::uint8_t> laszip(file.begin() + kAutzenTable, file.end());
    EXPECT_EQ(encode_table({{0, 283499}, {0, 262423}, {0, 55259}}, false), laszip);
}

TEST(ChunkTableWritten, ZeroByteChunk) {
    EditedFile f(kAutzen, [](auto& b) { replace_autzen_table(b, {{0, 283499}, {0, 0}, {0, 317682}}, false); });
    EXPECT_TRUE(contains(rejection(f.path()), "chunk 1 at byte 285651 has a size of 0 bytes"));
}

TEST(ChunkTableWritten, VariableChunks) {
    EditedFile f(kAutzen, [](auto& b) {
        replace_autzen_table(b, {{60000, 283499}, {30000, 262423}, {20000, 55259}}, true);
    });
    const auto t = table_of(f.path());
    EXPECT_EQ(t.chunks(), (std::vector<Chunk>{{0, 60000, 2152, 283499},
                                            {60000, 30000, 285651, 262423},
                                            {90000, 20000, 548074, 55259}}));
}

TEST(ChunkTableWritten, VariableChunkWithoutPoints) {
    EditedFile f(kAutzen, [](auto& b) {
        replace_autzen_table(b, {{60000, 283499}, {0, 262423}, {50000, 55259}}, true);
    });
    EXPECT_TRUE(contains(rejection(f.path()), "chunk 1 at byte 285651 holds no points"));
}

TEST(ChunkTableWritten, LargeTableIsReadInGrowingWindows) {
    // 60,000 small chunks of random sizes: the coded table is larger than the first read
    // window, so it is read again with larger ones.
    std::vector<Entry> entries(60000);
    std::uint32_t x = 12345;
    std::uint64_t points = 0;
    for (auto& e : entries) {
        x = x * 1664525u + 1013904223u;
        e = {1 + (x >> 8) % 4095, 1 + (x >> 20) % 9};
        points += e.points;
    }
    ASSERT_GT(encode_table(entries, true).size(), 4096u + 24u * 4096u);
    EditedFile f(kAutzen, [&](auto& b) {
        replace_autzen_table(b, entries, true);
        poke<std::uint32_t>(b, kLegacyCountField, static_cast<std::uint32_t>(points));
    });
    const auto t = table_of(f.path());
    ASSERT_EQ(t.chunks().size(), entries.size());
    std::uint64_t first = 0, offset = kAutzenPosition + 8;
    for (std::size_t i = 0; i < entries.size(); ++i) {
        ASSERT_EQ(t.chunks()[i], (Chunk{first, entries[i].points, offset, entries[i].bytes})) << i;
        first += entries[i].points;
        offset += entries[i].bytes;
    }
}

// The compact form gives the chunks it was made from: 8 bytes a chunk when all but the last hold the
// same count, 16 when counts vary; chunks that are not back to back are refused.
TEST(ChunkTableForm, KeepsTheChunksInEightOrSixteenBytesEach) {
    const std::vector<Chunk> fixed{{0, 100, 500, 40}, {100, 100, 540, 30}, {200, 7, 570, 9}};
    const ChunkTable regular(fixed);
    EXPECT_EQ(regular.chunks(), fixed);
    EXPECT_EQ(regular.back(), fixed.back());
    EXPECT_LE(regular.heap_bytes(), (fixed.size() + 1) * 8);

    const std::vector<Chunk> variable{{0, 100, 500, 40}, {100, 120, 540, 30}, {220, 1, 570, 9}};
    const ChunkTable counted(variable);
    EXPECT_EQ(counted.chunks(), variable);
    EXPECT_EQ(counted[1], variable[1]);
    EXPECT_LE(counted.heap_bytes(), (variable.size() + 1) * 16);
    EXPECT_GT(counted.heap_bytes(), regular.heap_bytes());

    const std::vector<Chunk> last_larger{{0, 100, 500, 40}, {100, 150, 540, 30}};
    EXPECT_EQ(ChunkTable(last_larger).chunks(), last_larger);
    EXPECT_TRUE(ChunkTable(std::vector<Chunk>{}).empty());
    EXPECT_THROW(ChunkTable(std::vector<Chunk>{{0, 100, 500, 40}, {100, 100, 541, 30}}), Error);  // a gap
    EXPECT_THROW(ChunkTable(std::vector<Chunk>{{0, 100, 500, 40}, {90, 100, 540, 30}}), Error);   // points overlap
}

}  // namespace
}  // namespace lidarscout::laz
