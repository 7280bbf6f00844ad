// The LAZ chunk encoder (compressor 2, point formats 0-5), the chunk table writer and the
// LASzip VLR writer:
// - bit-exactness: for every (LAS, LAZ) pair of formats/expected/encode_pairs.json, and every
//   LAZ file with wave packets that LASzip wrote from a LAS file of formats/ (the same
//   points_sha256 in expected/), encoding the LAS records in chunks of the pair's chunk size
//   reproduces the LAZ's chunk bytes and its chunk table byte for byte, with the VLR of
//   make_laszip_vlr;
// - losslessness: every point10 LAS file of formats/ and chunks of the Kentucky survey
//   tiles come back unchanged through encode_chunk -> decode_chunk, as do synthetic records
//   that exercise every branch of the item encoders (wave packets of formats 4 and 5 too);
// - chunk tables (fixed and variable) round-trip through read_chunk_table;
// - bad input (item lists, sizes, formats) is rejected with an Error.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "dataset/tile.hpp"
#include "io/file.hpp"
#include "las/header.hpp"
#include "las/laszip_vlr.hpp"
#include "las/point_format.hpp"
#include "laz/chunk_decoder.hpp"
#include "laz/chunk_encoder.hpp"
#include "laz/laz.hpp"
#include "laz/chunk_table_writer.hpp"
#include "laz/laszip_vlr_writer.hpp"
#include "laz/chunk_codec_helpers.hpp"
#include "test_data.hpp"

namespace lidarscout::laz {
namespace {

namespace fs = std::filesystem;
using namespace codec_test;

constexpr std::uint32_t kDefaultChunkSize = 50000;

// ---- helpers ----------------------------------------------------------------------------

// All point records of an uncompressed LAS file.
std::vector<std::uint8_t> las_records(const io::File& file, const dataset::Tile& tile) {
    const std::size_t bytes = tile.header.point_count * tile.header.record_length;
    return file.read_vector(tile.header.offset_to_point_data, bytes, "point records");
}

const las::Vlr& laszip_vlr_of(const dataset::Tile& tile) {
    for (const las::Vlr& v : tile.vlrs()) {
        if (v.is("laszip encoded", 22204)) return v;
    }
    throw Error(tile.path(), std::nullopt, "test: no laszip VLR");
}

bool same_items(const las::LaszipVlr& a, const las::LaszipVlr& b) {
    return std::equal(a.items.begin(), a.items.end(), b.items.begin(), b.items.end(), [](const auto& x, const auto& y) {
        return x.type == y.type && x.size == y.size && x.version == y.version;
    });
}

// ---- bit-exactness on the encode pairs ----------------------------------------------------

struct Pair {
    fs::path las;
    fs::path laz;
    std::uint32_t chunk_size = 0;
};

void PrintTo(const Pair& p, std::ostream* os) { *os << p.laz.filename().string(); }

std::vector<Pair> encode_pairs() {
    std::vector<Pair> pairs;
    for (const auto& j : test::read_json(test::formats_dir() / "expected" / "encode_pairs.json")) {
        pairs.push_back({test::formats_dir() / j.at("las").get<std::string>(),
                         test::formats_dir() / j.at("laz").get<std::string>(),
                         j.at("chunk_size").get<std::uint32_t>()});
    }
    return pairs;
}

std::string pair_name(const testing::TestParamInfo<Pair>& info) {
    std::string name = std::to_string(info.index) + "_" + info.param.laz.filename().string();
    for (char& c : name) {
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
    }
    return name;
}

// The bytes of the LAZ's chunk table as stored: from its position to the end of its region
// (the EVLRs, the trailing position int64, or the end of the file).
std::vector<std::uint8_t> stored_table(const io::File& file, const dataset::Tile& tile) {
    const ChunkTable& t = tile.chunks().value();
    std::uint64_t end = file.size();
    if (t.offset_from_file_end) end -= 8;
    if (tile.header.number_of_evlrs > 0 && tile.header.evlr_offset > t.table_offset && tile.header.evlr_offset < end) {
        end = tile.header.evlr_offset;
    }
    return file.read_vector(t.table_offset, end - t.table_offset, "chunk table");
}

class EncodePairs : public testing::TestWithParam<Pair> {};

TEST_P(EncodePairs, ChunksAndTableAreByteIdentical) {
    const Pair& pair = GetParam();
    const auto las_file = io::File::open(pair.las.string());
    const auto laz_file = io::File::open(pair.laz.string());
    const auto las_tile = dataset::read_tile(las_file);
    const auto laz_tile = dataset::read_tile(laz_file);
    ASSERT_FALSE(las_tile.compressed());
    ASSERT_TRUE(laz_tile.compressed());

    const las::LaszipVlr laz =
        make_laszip_vlr(las_tile.header.point_format, las_tile.header.record_length, pair.chunk_size);
    EXPECT_TRUE(same_items(laz, *laz_tile.laz())) << "make_laszip_vlr chose other items than the file has";
    EXPECT_EQ(laz.compressor, laz_tile.laz()->compressor);
    EXPECT_EQ(laz.chunk_size, laz_tile.laz()->chunk_size);

    const auto records = las_records(las_file, las_tile);
    const auto& stored_chunks = laz_tile.chunks().value().chunks();
    const Encoded ours = encode_in_chunks(laz, records, pair.chunk_size);
    ASSERT_EQ(ours.chunks.size(), stored_chunks.size());
    std::size_t identical = 0;
    for (std::size_t i = 0; i < ours.chunks.size(); ++i) {
        const Chunk& c = stored_chunks[i];
        ASSERT_EQ(ours.chunks[i].point_count, c.point_count) << "chunk " << i;
        const auto stored = laz_file.read_vector(c.byte_offset, c.byte_size, "chunk");
        const auto mine = std::span(ours.bytes).subspan(ours.chunks[i].byte_offset, ours.chunks[i].byte_size);
        const bool same = std::equal(mine.begin(), mine.end(), stored.begin(), stored.end());
        identical += same;
        EXPECT_TRUE(same) << "chunk " << i << ": " << mine.size() << " bytes encoded, " << stored.size()
                          << " stored, first difference at byte "
                          << (std::mismatch(mine.begin(), mine.end(), stored.begin(), stored.end()).first -
                              mine.begin());
    }
    EXPECT_EQ(identical, ours.chunks.size());

    // Some writers (liblas, laz-perf's test sets) leave 32 more bytes after the table; the
    // table itself is the coded part, which ends with LASzip's padding.
    const auto table = encode_chunk_table(ours.chunks, has_variable_chunks(laz));
    const auto stored = stored_table(laz_file, laz_tile);
    ASSERT_GE(stored.size(), table.size());
    EXPECT_EQ(table, std::vector<std::uint8_t>(stored.begin(), stored.begin() + static_cast<long>(table.size())))
        << "chunk table";
    if (stored.size() != table.size()) {
        EXPECT_EQ(stored.size() - table.size(), 32u);
    }
}

INSTANTIATE_TEST_SUITE_P(Formats, EncodePairs, testing::ValuesIn(encode_pairs()), pair_name);

// The LAZ files with wave packets (formats 4, 5, 9, 10) whose records are those of a LAS file of
// formats/ (the same points_sha256 in expected/), when their items are the ones we write.
std::vector<Pair> wave_packet_twins() {
    std::vector<Pair> pairs;
    const auto all = test::all_expected();
    for (const auto& laz : all) {
        const auto& h = laz.json->at("header");
        if (h.is_null() || !h.at("compressed").get<bool>() || laz.json->at("reference_result") != "decodes") continue;
        const int format = h.at("point_format").get<int>();
        if (las::point_format_info(static_cast<std::uint8_t>(format)).wave_offset < 0) continue;
        const auto chunk_size = laz.json->at("laz").at("chunk_size").get<std::uint32_t>();
        const auto ours = make_laszip_vlr(static_cast<std::uint8_t>(format), h.at("record_length").get<std::uint16_t>(),
                                          chunk_size);
        const auto file = io::File::open(laz.file.string());
        if (!same_items(ours, *dataset::read_tile(file).laz())) continue;  // e.g. items version 4
        for (const auto& las : all) {
            const auto& lh = las.json->at("header");
            if (lh.is_null() || lh.at("compressed").get<bool>()) continue;
            if (las.json->value("points_sha256", "") == laz.json->at("points_sha256")) {
                pairs.push_back({las.file, laz.file, chunk_size});
            }
        }
    }
    return pairs;
}

INSTANTIATE_TEST_SUITE_P(WavePackets, EncodePairs, testing::ValuesIn(wave_packet_twins()), pair_name);

TEST(EncodePairsList, HoldsTheWavePacketTwins) {
    // pdrf4-1.3 and pdrf5-1.3 (point-wise, WAVEPACKET13 v1, by LASzip 3.5), pdrf9-1.4 and
    // pdrf10-1.4 (layered, WAVEPACKET14 v3, by LASzip 2.2); the 1.5 files use items version 4.
    std::set<std::string> twins;
    for (const Pair& p : wave_packet_twins()) twins.insert(p.laz.filename().string());
    EXPECT_EQ(twins, (std::set<std::string>{"modules__las__test__data__pdrf10-1.4.laz",
                                            "modules__las__test__data__pdrf4-1.3.laz",
                                            "modules__las__test__data__pdrf5-1.3.laz",
                                            "modules__las__test__data__pdrf9-1.4.laz"}));
}

TEST(EncodePairsList, HoldsThePoint10Pairs) {
    // The bit-exactness test above must not pass by finding no pairs.
    std::size_t point10 = 0;
    for (const Pair& p : encode_pairs()) {
        const auto file = io::File::open(p.las.string());
        point10 += dataset::read_tile(file).header.point_format <= 3;
    }
    EXPECT_EQ(point10, 27u);
}

// ---- losslessness ----------------------------------------------------------------------

void expect_round_trip(const las::LaszipVlr& laz, std::span<const std::uint8_t> records, std::uint64_t chunk_size,
                       const std::string& what) {
    const Encoded e = encode_in_chunks(laz, records, chunk_size);
    const auto back = decode_chunks(laz, e);
    EXPECT_EQ(first_difference(back, records, laz.record_length()), -1) << what << ", chunks of " << chunk_size;
}

TEST(ChunkEncoder, EveryPoint10LasFileRoundTrips) {
    std::size_t files = 0, with_extra_bytes = 0;
    for (const auto& e : test::all_expected()) {
        const auto& h = e.json->at("header");
        if (h.is_null() || h.at("compressed").get<bool>() || h.at("point_format").get<int>() > 5) continue;
        if (e.json->at("reference_result") != "decodes") continue;
        const auto file = io::File::open(e.file.string());
        const auto tile = dataset::read_tile(file);
        if (tile.header.point_count == 0) continue;
        const auto laz = make_laszip_vlr(tile.header.point_format, tile.header.record_length, kDefaultChunkSize);
        const auto records = las_records(file, tile);
        expect_round_trip(laz, records, kDefaultChunkSize, e.name);
        // Small chunks: many chunk starts, and chunks of one and two points.
        const std::size_t few = std::min<std::size_t>(tile.header.point_count, 300) * tile.header.record_length;
        for (std::uint64_t size : {1u, 2u, 7u}) expect_round_trip(laz, std::span(records).first(few), size, e.name);
        ++files;
        with_extra_bytes += laz.items.back().type == static_cast<std::uint16_t>(las::ItemType::Byte);
    }
    EXPECT_GE(files, 47u);  // 45 of formats 0-3, pdrf4 and pdrf5
    EXPECT_GE(with_extra_bytes, 5u);
}

// Decodes a few chunks of every Kentucky survey tile, re-encodes them, decodes again.
// The tiles were written by LASzip, so the re-encoded chunks are also the stored bytes.
TEST(ChunkEncoder, SurveyTilesRoundTripAndReencodeIdentically) {
    std::size_t chunks = 0, identical = 0;
    for (const auto& dir : fs::directory_iterator(test::surveys_dir())) {
        if (dir.path().filename().string().rfind("ky-", 0) != 0) continue;
        for (const auto& entry : fs::directory_iterator(dir.path())) {
            if (entry.path().extension() != ".laz") continue;
            const auto file = io::File::open(entry.path().string());
            const auto tile = dataset::read_tile(file);
            const auto& all = tile.chunks().value().chunks();
            const std::size_t rl = tile.header.record_length;
            for (std::size_t i : {std::size_t{0}, all.size() / 2, all.size() - 1}) {
                const Chunk& c = all[i];
                const auto stored = file.read_vector(c.byte_offset, c.byte_size, "chunk");
                std::vector<std::uint8_t> records(c.point_count * rl);
                decode_chunk(*tile.laz(), {stored, c.point_count, records});
                std::vector<std::uint8_t> again;
                encode_chunk(*tile.laz(), records, c.point_count, again);
                std::vector<std::uint8_t> back(records.size());
                decode_chunk(*tile.laz(), {again, c.point_count, back});
                EXPECT_EQ(first_difference(back, records, rl), -1) << entry.path() << " chunk " << i;
                identical += again == stored;
                ++chunks;
            }
        }
    }
    EXPECT_GE(chunks, 30u);
    EXPECT_EQ(identical, chunks) << "re-encoded survey chunks that differ from the stored ones";
}

// Synthetic records of format 3 with 5 extra bytes that reach every branch of the item
// encoders: all return-number combinations (also invalid ones), every attribute changing
// or not, XYZ jumps of any size, colours grey and not, and GPS times that repeat, advance
// by multiples of the last step (positive, negative, extreme), jump far away and back to
// earlier sequences (more than four of them).
std::vector<std::uint8_t> synthetic_records(std::size_t n, std::uint32_t seed) {
    constexpr std::size_t kRl = 39;
    std::mt19937 rng(seed);
    std::vector<std::uint8_t> out(n * kRl);
    std::int32_t x = 1000, y = -5000, z = 300;
    std::uint8_t flags = 0x11, cls = 2, angle = 0, user = 0;
    std::uint16_t intensity = 100, source = 7;
    double times[6] = {1000.0, 5.0e8, -3.0e5, 1.0e12, 42.0, 7.0e9};
    int seq = 0;
    double step = 1.0e-5;
    std::uint16_t rgb[3] = {100, 100, 100};
    std::uint8_t extra[5] = {0, 0, 0, 0, 0};
    const auto sometimes = [&](unsigned one_in) { return rng() % one_in == 0; };
    for (std::size_t i = 0; i < n; ++i) {
        std::uint8_t* r = out.data() + i * kRl;
        const auto big = [&]() { return static_cast<std::int32_t>(rng()); };
        const std::int32_t jump = sometimes(50) ? big() : static_cast<std::int32_t>(rng() % 2001) - 1000;
        x = static_cast<std::int32_t>(static_cast<std::uint32_t>(x) + static_cast<std::uint32_t>(jump));
        y = static_cast<std::int32_t>(static_cast<std::uint32_t>(y) + (sometimes(40) ? rng() : rng() % 301 - 150));
        z = sometimes(30) ? big() : z + static_cast<std::int32_t>(rng() % 41) - 20;
        if (sometimes(4)) {
            flags = static_cast<std::uint8_t>(sometimes(3) ? rng() : (1 + rng() % 5) | ((1 + rng() % 5) << 3));
        }
        if (sometimes(3)) intensity = static_cast<std::uint16_t>(sometimes(5) ? rng() : intensity + rng() % 21 - 10);
        if (sometimes(10)) cls = static_cast<std::uint8_t>(rng());
        if (sometimes(10)) angle = static_cast<std::uint8_t>(angle + rng() % 7 - 3);
        if (sometimes(20)) user = static_cast<std::uint8_t>(rng());
        if (sometimes(30)) source = static_cast<std::uint16_t>(rng());
        std::memcpy(r + 0, &x, 4);
        std::memcpy(r + 4, &y, 4);
        std::memcpy(r + 8, &z, 4);
        std::memcpy(r + 12, &intensity, 2);
        r[14] = flags;
        r[15] = cls;
        r[16] = angle;
        r[17] = user;
        std::memcpy(r + 18, &source, 2);

        const unsigned t = rng() % 100;
        if (t < 10) {
            // unchanged time
        } else if (t < 20) {
            seq = static_cast<int>(rng() % 6);  // to another (possibly new, possibly forgotten) sequence
        } else if (t < 25) {
            step *= (sometimes(2) ? 1 : -1) * static_cast<double>(1 + rng() % 700);  // multiples, also extreme
        } else if (t < 28) {
            step = 1.0e-5 * (1 + rng() % 3);
        } else if (t < 30) {
            times[seq] = std::ldexp(static_cast<double>(rng()), static_cast<int>(rng() % 60) - 20);
        }
        if (t >= 10) times[seq] += step;
        std::memcpy(r + 20, &times[seq], 8);

        if (sometimes(3)) {
            if (sometimes(4)) {
                rgb[0] = rgb[1] = rgb[2] = static_cast<std::uint16_t>(rng());  // grey
            } else {
                for (auto& c : rgb) c = static_cast<std::uint16_t>(sometimes(3) ? rng() : c + rng() % 11 - 5);
            }
        }
        std::memcpy(r + 28, rgb, 6);
        for (auto& b : extra) {
            if (sometimes(4)) b = static_cast<std::uint8_t>(sometimes(2) ? rng() : b + 1);
        }
        std::memcpy(r + 34, extra, 5);
    }
    return out;
}

TEST(ChunkEncoder, SyntheticRecordsOfEveryItemRoundTrip) {
    const auto records = synthetic_records(60000, 3);
    for (std::uint8_t format : {0, 1, 2, 3}) {
        // The same bytes, cut to each format's layout (GPS and RGB where the format has them).
        static constexpr std::uint16_t kSizes[] = {20, 28, 26, 34};
        const std::uint16_t rl = kSizes[format] + 5;
        std::vector<std::uint8_t> cut;
        for (std::size_t i = 0; i < 60000; ++i) {
            const std::uint8_t* r = records.data() + i * 39;
            cut.insert(cut.end(), r, r + 20);
            if (format == 1 || format == 3) cut.insert(cut.end(), r + 20, r + 28);
            if (format == 2 || format == 3) cut.insert(cut.end(), r + 28, r + 34);
            cut.insert(cut.end(), r + 34, r + 39);
        }
        const auto laz = make_laszip_vlr(format, rl, kDefaultChunkSize);
        expect_round_trip(laz, cut, kDefaultChunkSize, "format " + std::to_string(format));
        expect_round_trip(laz, std::span(cut).first(997u * rl), 97, "format " + std::to_string(format));
    }
}

// The synthetic records with wave packets of every kind (wave_packets): format 5 (format 3's
// fields, the packet, 5 extra bytes) and format 4 (the same without colour).
TEST(ChunkEncoder, SyntheticWavePacketsRoundTrip) {
    constexpr std::size_t kPoints = 6000;
    const auto records = synthetic_records(kPoints, 4);
    const auto packets = wave_packets(kPoints, 9);
    const auto f5 = with_wave_packets(records, 39, 34, packets);
    std::vector<std::uint8_t> no_rgb;
    for (std::size_t i = 0; i < kPoints; ++i) {
        const std::uint8_t* r = records.data() + i * 39;
        no_rgb.insert(no_rgb.end(), r, r + 28);
        no_rgb.insert(no_rgb.end(), r + 34, r + 39);
    }
    const auto f4 = with_wave_packets(no_rgb, 33, 28, packets);
    for (const auto& [format, cut] : {std::pair{std::uint8_t{5}, f5}, std::pair{std::uint8_t{4}, f4}}) {
        const std::size_t rl = cut.size() / kPoints;
        const auto laz = make_laszip_vlr(format, static_cast<std::uint16_t>(rl), kDefaultChunkSize);
        ASSERT_EQ(laz.items.size(), format == 5 ? 5u : 4u);
        for (std::uint64_t size : {std::uint64_t{kDefaultChunkSize}, std::uint64_t{97}, std::uint64_t{2}}) {
            expect_round_trip(laz, cut, size, "format " + std::to_string(format));
        }
    }
}

TEST(ChunkEncoder, OnePointChunkIsTheRecordAndAnEmptyStream) {
    const auto laz = make_laszip_vlr(1, 28, kDefaultChunkSize);
    const auto records = synthetic_records(1, 5);
    std::vector<std::uint8_t> rec(records.begin(), records.begin() + 28);
    std::vector<std::uint8_t> out = {0xAA};
    encode_chunk(laz, rec, 1, out);
    std::vector<std::uint8_t> expected = {0xAA};
    expected.insert(expected.end(), rec.begin(), rec.end());
    expected.insert(expected.end(), {0x01, 0, 0, 0});
    EXPECT_EQ(out, expected);
}

TEST(ChunkEncoder, RejectsWhatItCannotEncode) {
    const auto records = synthetic_records(20, 1);
    const auto expect_error = [](const las::LaszipVlr& laz, std::span<const std::uint8_t> r, std::uint64_t n,
                                 const std::string& part) {
        std::vector<std::uint8_t> out;
        try {
            encode_chunk(laz, r, n, out);
            ADD_FAILURE() << "no error, expected one containing '" << part << "'";
        } catch (const Error& e) {
            EXPECT_NE(e.cause().find(part), std::string::npos) << e.cause();
        }
    };
    auto laz = make_laszip_vlr(3, 39, kDefaultChunkSize);
    expect_error(laz, records, 19, "records");                          // size mismatch
    expect_error(laz, std::span(records).first(0), 0, "at least one");  // empty chunk
    auto wave_v2 = make_laszip_vlr(4, 57, kDefaultChunkSize);
    wave_v2.items[2].version = 2;  // WAVEPACKET13 exists only in version 1
    expect_error(wave_v2, std::span(records).first(570), 10, "WAVEPACKET13 v2");
    auto v1 = laz;
    v1.items[0].version = 1;
    expect_error(v1, records, 20, "unsupported item list");
    auto reordered = laz;
    std::swap(reordered.items[1], reordered.items[2]);
    expect_error(reordered, records, 20, "unsupported item list");
    auto compressor1 = laz;
    compressor1.compressor = 1;
    expect_error(compressor1, records, 20, "compressor 1");
}

// ---- the chunk table ---------------------------------------------------------------------

// Writes a file with `chunks` and their table, as a LAZ writer lays them out, and reads the
// table back. The chunk bytes are left as a hole (a sparse file), so chunks may be large.
std::vector<Chunk> write_and_read_table(const std::vector<Chunk>& chunks, std::uint32_t chunk_size) {
    constexpr std::uint32_t kPointData = 500;  // where the chunk table position goes
    las::Header header;
    header.offset_to_point_data = kPointData;
    const las::LaszipVlr laz = make_laszip_vlr(1, 28, chunk_size);
    std::uint64_t points = 0, table_at = kPointData + 8;
    for (const Chunk& c : chunks) {
        table_at += c.byte_size;
        points += c.point_count;
    }
    header.point_count = points;
    const auto table = encode_chunk_table(chunks, has_variable_chunks(laz));

    const fs::path path = fs::temp_directory_path() / ("lidarscout_table_" + std::to_string(getpid()) + ".laz");
    {
        std::ofstream out(path, std::ios::binary);
        const std::vector<char> start(kPointData, 0);
        out.write(start.data(), kPointData);
        out.write(reinterpret_cast<const char*>(&table_at), 8);
        out.seekp(static_cast<std::streamoff>(table_at));
        out.write(reinterpret_cast<const char*>(table.data()), static_cast<std::streamsize>(table.size()));
    }
    const auto f = io::File::open(path.string());
    auto read = read_chunk_table(f, header, laz).chunks();
    fs::remove(path);
    return read;
}

// Chunk positions as a writer lays them out after the position int64 at 500.
std::vector<Chunk> laid_out(std::vector<Chunk> chunks) {
    std::uint64_t first = 0, offset = 508;
    for (Chunk& c : chunks) {
        c.first_point = first;
        c.byte_offset = offset;
        first += c.point_count;
        offset += c.byte_size;
    }
    return chunks;
}

TEST(ChunkTableEncoder, VariableTablesRoundTrip) {
    std::mt19937 rng(4);
    for (std::size_t count : {1u, 2u, 5u, 3000u}) {
        std::vector<Chunk> chunks(count);
        for (Chunk& c : chunks) {
            c.point_count = rng() % 3 == 0 ? 1 + rng() % 100000 : 50000;
            c.byte_size = rng() % 5 == 0 ? 1 + rng() % 5000000 : 8 + rng() % 1000;
        }
        chunks = laid_out(chunks);
        EXPECT_EQ(write_and_read_table(chunks, las::LaszipVlr::kVariableChunkSize), chunks) << count << " chunks";
    }
    // Entries at the ends of the 32-bit range: the differences between them wrap.
    const std::uint64_t max = std::numeric_limits<std::uint32_t>::max();
    const auto extreme = laid_out({{0, max, 0, max}, {0, 1, 0, 1}, {0, max - 1, 0, 2}, {0, 2, 0, 1}});
    EXPECT_EQ(write_and_read_table(extreme, las::LaszipVlr::kVariableChunkSize), extreme);
}

TEST(ChunkTableEncoder, FixedTablesRoundTripWithoutPointCounts) {
    std::vector<Chunk> chunks = {{0, 1000, 0, 4000}, {0, 1000, 0, 3900}, {0, 1000, 0, 4100}, {0, 17, 0, 90}};
    chunks = laid_out(chunks);
    EXPECT_EQ(write_and_read_table(chunks, 1000), chunks);
    // Without point counts the table is smaller than the variable one of the same chunks.
    EXPECT_LT(encode_chunk_table(chunks, false).size(), encode_chunk_table(chunks, true).size());
}

TEST(ChunkTableEncoder, EmptyTableIsJustItsHeader) {
    EXPECT_EQ(encode_chunk_table({}, false), (std::vector<std::uint8_t>{0, 0, 0, 0, 0, 0, 0, 0}));
}

TEST(ChunkTableEncoder, RejectsCountsBeyond32Bits) {
    EXPECT_THROW(encode_chunk_table({{0, 10, 0, std::uint64_t{1} << 32}}, false), Error);
    EXPECT_THROW(encode_chunk_table({{0, std::uint64_t{1} << 32, 0, 10}}, true), Error);
    EXPECT_NO_THROW(encode_chunk_table({{0, std::uint64_t{1} << 32, 0, 10}}, false));  // counts not stored
}

// ---- the LASzip VLR ------------------------------------------------------------------------

TEST(LaszipVlrEncoder, PayloadsMatchThePairFiles) {
    std::size_t exact = 0, checked = 0;
    for (const Pair& p : encode_pairs()) {
        const auto file = io::File::open(p.laz.string());
        const auto tile = dataset::read_tile(file);
        const las::Vlr& stored = laszip_vlr_of(tile);
        auto mine = make_laszip_vlr(tile.header.point_format, tile.header.record_length, p.chunk_size);
        if (serialize_laszip_vlr(mine) == stored.data) ++exact;  // written by LASzip 3.4.3
        // Other writers' versions aside, every field must agree.
        mine.version_major = tile.laz()->version_major;
        mine.version_minor = tile.laz()->version_minor;
        mine.version_revision = tile.laz()->version_revision;
        EXPECT_EQ(serialize_laszip_vlr(mine), stored.data) << p.laz;
        ++checked;
    }
    EXPECT_EQ(checked, 30u);
    EXPECT_GE(exact, 8u);
}

TEST(LaszipVlrEncoder, EveryFormatParsesBack) {
    for (std::uint8_t format = 0; format <= 10; ++format) {
        for (std::uint16_t extra : {0, 1, 13}) {
            const std::uint16_t rl = las::point_format_info(format).size + extra;
            const auto vlr = make_laszip_vlr(format, rl, 50000);
            const auto payload = serialize_laszip_vlr(vlr);
            EXPECT_EQ(payload.size(), 34 + 6 * vlr.items.size());
            const auto parsed = las::parse_laszip_vlr(payload, "test", 0);
            EXPECT_TRUE(same_items(parsed, vlr)) << int{format};
            EXPECT_EQ(parsed.record_length(), rl) << int{format};
            EXPECT_EQ(parsed.compressor, format <= 5 ? 2 : 3);
            EXPECT_EQ(parsed.chunk_size, 50000u);
            EXPECT_EQ(parsed.number_of_special_evlrs, -1);
        }
    }
    const auto f10 = make_laszip_vlr(10, 67 + 2, 50000);
    const std::vector<std::uint16_t> types = {10, 12, 13, 14};
    ASSERT_EQ(f10.items.size(), types.size());
    for (std::size_t i = 0; i < types.size(); ++i) EXPECT_EQ(f10.items[i].type, types[i]);
}

TEST(LaszipVlrEncoder, RejectsImpossibleRequests) {
    EXPECT_THROW(make_laszip_vlr(11, 40, 50000), Error);
    EXPECT_THROW(make_laszip_vlr(3, 33, 50000), Error);
    EXPECT_THROW(make_laszip_vlr(3, 34, 0), Error);
    EXPECT_TRUE(make_laszip_vlr(3, 34, las::LaszipVlr::kVariableChunkSize).variable_chunks());
}

}  // namespace
}  // namespace lidarscout::laz
