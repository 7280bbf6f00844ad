// Every file the reference LASzip decodes (144: LAS and all LAZ variants) gives the same
// SHA-256 over its point records through for_each_record_batch, whatever the batch size and
// with or without read-ahead; and a LAZ file's decode units decoded one by one, last first
// (DecodeUnits, as the viewer reads them: every other from its bytes read already), placed at their first
// point, give it too.
#include <gtest/gtest.h>

#include "core/error.hpp"
#include "core/sha256.hpp"
#include "core/thread_pool.hpp"
#include "dataset/point_reader.hpp"
#include "dataset/tile.hpp"
#include "io/file.hpp"
#include "test_data.hpp"

namespace lidarscout {
namespace {

using test::Expected;

std::vector<Expected> decodable() {
    std::vector<Expected> out;
    for (auto& e : test::all_expected()) {
        if (e.json->at("reference_result") == "decodes") out.push_back(std::move(e));
    }
    return out;
}

std::string checksum(const std::string& path, std::uint64_t batch_points, std::uint64_t& points,
                     bool read_ahead = false) {
    auto file = io::File::open(path);
    auto tile = dataset::read_tile(file);
    static ThreadPool pool(2);
    Sha256 sha;
    points = 0;
    dataset::for_each_record_batch(file, tile, pool, [&](std::uint64_t first, std::span<const std::uint8_t> records) {
        EXPECT_EQ(first, points);
        points += records.size() / tile.header.record_length;
        sha.update(records);
    }, las::fields::kAll, batch_points, read_ahead);
    EXPECT_EQ(points, tile.header.point_count);
    return sha.hex_digest();
}

class PointsSha256 : public ::testing::TestWithParam<Expected> {};

TEST_P(PointsSha256, MatchesReference) {
    const auto& e = GetParam();
    std::uint64_t points = 0;
    EXPECT_EQ(checksum(e.file.string(), 1u << 20, points), e.json->at("points_sha256").get<std::string>());
    // Small batches: many batch boundaries (one chunk each for LAZ, 997 records for LAS).
    EXPECT_EQ(checksum(e.file.string(), 997, points), e.json->at("points_sha256").get<std::string>());
    // The same with the next batch read while this one is used.
    EXPECT_EQ(checksum(e.file.string(), 997, points, true), e.json->at("points_sha256").get<std::string>());
}

TEST_P(PointsSha256, DecodeUnitsInAnyOrderMatchReference) {
    const auto& e = GetParam();
    auto file = io::File::open(e.file.string());
    auto tile = dataset::read_tile(file);
    if (!tile.compressed()) {
        EXPECT_THROW(dataset::DecodeUnits{tile}, Error);  // a LAS file has no units
        return;
    }
    const dataset::DecodeUnits units(tile);
    const std::size_t record = tile.header.record_length;
    std::vector<std::uint8_t> records(tile.header.point_count * record), scratch;
    std::uint64_t covered = 0;
    for (std::size_t u = units.size(); u-- > 0;) {
        const auto out = std::span(records).subspan(units.first_point(u) * record, units.point_count(u) * record);
        if (u % 2 == 0) {
            units.decode(file, u, out, las::fields::kAll, scratch);
        } else {  // (every other from its bytes read already, as a remote tile's piece is)
            const auto bytes = file.read_vector(units.byte_offset(u), units.byte_size(u));
            units.decode_bytes(file.path(), u, bytes, out, las::fields::kAll);
            EXPECT_THROW(units.decode_bytes(file.path(), u, std::span(bytes).first(bytes.size() - 1), out,
                                            las::fields::kAll), Error) << "a chunk's bytes cut short";
        }
        covered += units.point_count(u);
    }
    EXPECT_EQ(covered, tile.header.point_count);
    Sha256 sha;
    sha.update(records);
    EXPECT_EQ(sha.hex_digest(), e.json->at("points_sha256").get<std::string>());
}

std::string test_name(const ::testing::TestParamInfo<Expected>& info) {
    std::string s = info.param.name;
    for (char& c : s) if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
    return s;
}

INSTANTIATE_TEST_SUITE_P(Formats, PointsSha256, ::testing::ValuesIn(decodable()), test_name);

TEST(PointsSha256Corpus, AllDecodableFiles) {
    // Every hash is in file order (COPC included: the reference reads it as LASzip's library does).
    EXPECT_EQ(decodable().size(), 144u);
}

}  // namespace
}  // namespace lidarscout
