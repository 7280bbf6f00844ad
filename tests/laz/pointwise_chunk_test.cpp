// Point-wise LAZ decoding (compressors 1 and 2, point10-family items): every corpus file
// the reference decodes gives bit-identical records (SHA-256 over all records); truncated
// or corrupted chunks end in an Error or a wrong checksum, never in a crash or a hang;
// unsupported item lists are rejected.
#include <gtest/gtest.h>


#include <random>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/sha256.hpp"
#include "dataset/tile.hpp"
#include "io/file.hpp"
#include "laz/pointwise_chunk.hpp"
#include "test_data.hpp"

namespace lidarscout {
namespace {

using test::Expected;

// One stream of compressed points: a chunk (compressor 2), or all point data (compressor 1).
struct Stream {
    std::vector<std::uint8_t> bytes;
    std::uint64_t point_count = 0;
};

struct LoadedFile {
    las::LaszipVlr laz;
    std::size_t record_length = 0;
    std::uint64_t point_count = 0;
    std::vector<Stream> streams;
};

LoadedFile load(const std::string& path) {
    auto file = io::File::open(path);
    auto tile = dataset::read_tile(file);
    LoadedFile out;
    out.laz = tile.laz().value();
    out.record_length = tile.header.record_length;
    out.point_count = tile.header.point_count;
    if (tile.laz()->compressor == 1) {
        // No chunk table: one stream from the raw first point to the end of the point data.
        const std::uint64_t end = tile.header.number_of_evlrs ? tile.header.evlr_offset : file.size();
        const std::uint64_t start = tile.header.offset_to_point_data;
        out.streams.push_back({file.read_vector(start, end - start), out.point_count});
    } else {
        for (const auto& c : tile.chunks().value()) {
            out.streams.push_back({file.read_vector(c.byte_offset, c.byte_size), c.point_count});
        }
    }
    return out;
}

// Decodes every stream of `f` into one buffer of records.
std::vector<std::uint8_t> decode_all(const LoadedFile& f, std::uint32_t fields = laz::fields::kAll) {
    std::vector<std::uint8_t> out(f.point_count * f.record_length);
    std::size_t at = 0;
    for (const Stream& s : f.streams) {
        const std::size_t n = s.point_count * f.record_length;
        laz::decode_pointwise_chunk(f.laz, {s.bytes, s.point_count, std::span(out).subspan(at, n), fields});
        at += n;
    }
    EXPECT_EQ(at, out.size());
    return out;
}

std::vector<Expected> pointwise_files() {
    std::vector<Expected> out;
    for (auto& e : test::all_expected()) {
        const auto& j = *e.json;
        if (!j.contains("laz") || j.at("reference_result") != "decodes") continue;
        const int compressor = j.at("laz").at("compressor");
        if (compressor == 1 || compressor == 2) out.push_back(std::move(e));
    }
    return out;
}

std::string param_name(const ::testing::TestParamInfo<Expected>& info) {
    std::string s = info.param.name.substr(0, info.param.name.size() - 5);  // without ".json"
    for (char& c : s) {
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
    }
    return s;
}

class PointwiseDecode : public ::testing::TestWithParam<Expected> {};

TEST_P(PointwiseDecode, RecordsMatchReferenceSha256) {
    const Expected& e = GetParam();
    const LoadedFile f = load(e.file.string());
    ASSERT_EQ(f.record_length, f.laz.record_length());
    const std::vector<std::uint8_t> records = decode_all(f);
    EXPECT_EQ(sha256_hex(records), e.json->at("points_sha256").get<std::string>());
}

INSTANTIATE_TEST_SUITE_P(Corpus, PointwiseDecode, ::testing::ValuesIn(pointwise_files()), param_name);

// ---- damaged data ------------------------------------------------------------------------

// Small files covering every item codec: v2 POINT10/GPS/RGB, v1 items (compressor 1),
// WAVEPACKET13, BYTE.
const char* const kDamageFiles[] = {
    "PDAL__PDAL/test__data__apps__simple.laz",
    "PDAL__PDAL/test__data__apps__simple-laszip-compressor-version-1.2r0.laz",
    "cran__rlas/inst__extdata__fwf.laz",
    "visgl__loaders.gl/modules__las__test__data__pdrf5-1.3.laz",
    "hobuinc__laz-perf/cpp__test__raw-sets__extrabytes.laz",
    "laz-rs__laz-rs/tests__data__point-version-1-point-wise.laz",
};

// Decodes `f` with its streams replaced; true if that threw an Error, false if it finished.
// Either way it must not crash or hang (run under the sanitizers).
bool decode_throws(const LoadedFile& f, std::string* records_hash) {
    try {
        *records_hash = sha256_hex(decode_all(f));
        return false;
    } catch (const Error& err) {
        EXPECT_GT(err.cause().size(), 10u);
        return true;
    }
}

class PointwiseDamage : public ::testing::TestWithParam<const char*> {};

TEST_P(PointwiseDamage, TruncatedChunkFailsOrDiffers) {
    const LoadedFile good = load((test::formats_dir() / GetParam()).string());
    const std::string want = sha256_hex(decode_all(good));
    LoadedFile cut = good;
    for (Stream& s : cut.streams) s.bytes.resize(s.bytes.size() / 2);
    std::string got;
    if (!decode_throws(cut, &got)) {
        EXPECT_NE(got, want);
    }
}

TEST_P(PointwiseDamage, CorruptedChunkFailsOrDiffers) {
    const LoadedFile good = load((test::formats_dir() / GetParam()).string());
    const std::string want = sha256_hex(decode_all(good));
    std::mt19937 rng(1234);
    for (int trial = 0; trial < 8; ++trial) {
        LoadedFile bad = good;
        for (Stream& s : bad.streams) {
            // Flip bytes in the coded part (after the raw first record), densely on some trials.
            const std::size_t start = good.record_length;
            if (s.bytes.size() <= start + 1) continue;
            std::uniform_int_distribution<std::size_t> pos(start, s.bytes.size() - 1);
            const int flips = trial < 4 ? 1 + trial : 64 << trial;
            for (int i = 0; i < flips; ++i) s.bytes[pos(rng)] ^= static_cast<std::uint8_t>(1 + rng() % 255);
        }
        std::string got;
        if (!decode_throws(bad, &got)) {
            EXPECT_NE(got, want) << "trial " << trial;
        }
    }
}

// Streams overwritten with one byte value end (an error, or records that are not the original's),
// never a hang or a crash.
TEST_P(PointwiseDamage, ZeroedAndGarbageStreamsTerminate) {
    const LoadedFile good = load((test::formats_dir() / GetParam()).string());
    const std::string want = sha256_hex(decode_all(good));
    for (std::uint8_t fill : {std::uint8_t{0x00}, std::uint8_t{0xFF}, std::uint8_t{0x5A}}) {
        LoadedFile bad = good;
        for (Stream& s : bad.streams) std::fill(s.bytes.begin() + good.record_length, s.bytes.end(), fill);
        std::string got;
        if (!decode_throws(bad, &got)) {
            EXPECT_NE(got, want) << "fill " << int(fill);
        }
    }
}

INSTANTIATE_TEST_SUITE_P(Files, PointwiseDamage, ::testing::ValuesIn(kDamageFiles),
                         [](const ::testing::TestParamInfo<const char*>& info) {
                             std::string s = info.param;
                             for (char& c : s) {
                                 if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                             }
                             return s;
                         });

// ---- field selection and rejection --------------------------------------------------------

TEST(PointwiseFields, UnrequestedFieldsAreZeroRequestedOnesExact) {
    const LoadedFile f = load((test::formats_dir() / "PDAL__PDAL/test__data__apps__simple.laz").string());
    ASSERT_EQ(f.record_length, 34u);  // POINT10 + GPSTIME11 + RGB12
    const auto all = decode_all(f);
    const auto some = decode_all(f, laz::fields::kXyz | laz::fields::kClassification | laz::fields::kRgb);
    for (std::size_t r = 0; r < f.point_count; ++r) {
        const std::uint8_t* a = all.data() + r * 34;
        const std::uint8_t* b = some.data() + r * 34;
        for (std::size_t i = 0; i < 34; ++i) {
            const bool kept = i < 12 || i == 15 || i >= 28;
            ASSERT_EQ(b[i], kept ? a[i] : 0) << "record " << r << " byte " << i;
        }
    }
}

las::LaszipVlr vlr_with(std::vector<las::LazItem> items, std::uint16_t compressor = 2) {
    las::LaszipVlr laz;
    laz.compressor = compressor;
    laz.chunk_size = 50000;
    laz.items = std::move(items);
    return laz;
}

void expect_rejected(const las::LaszipVlr& laz, std::size_t bytes = 64, std::uint64_t points = 2,
                     std::size_t out_size = 0) {
    const std::vector<std::uint8_t> in(bytes, 0);
    std::vector<std::uint8_t> out(out_size ? out_size : points * laz.record_length());
    EXPECT_THROW(laz::decode_pointwise_chunk(laz, {in, points, out}), Error);
}

TEST(PointwiseReject, UnsupportedItemsAndSizes) {
    using T = las::ItemType;
    auto item = [](T t, std::uint16_t size, std::uint16_t version) {
        return las::LazItem{static_cast<std::uint16_t>(t), size, version};
    };
    expect_rejected(vlr_with({item(T::Point14, 30, 3)}));
    expect_rejected(vlr_with({item(T::Point10, 20, 2), item(T::Wavepacket13, 29, 2)}));
    expect_rejected(vlr_with({item(T::Point10, 20, 3)}));
    expect_rejected(vlr_with({item(T::Point10, 20, 2), item(T::Short, 2, 2)}));
    expect_rejected(vlr_with({item(T::Point10, 22, 2)}));
    expect_rejected(vlr_with({item(T::Point10, 20, 2), item(T::Byte, 0, 2)}));
    expect_rejected(vlr_with({}));
    expect_rejected(vlr_with({item(T::Point10, 20, 2)}, 3));
    auto coder = vlr_with({item(T::Point10, 20, 2)});
    coder.coder = 1;
    expect_rejected(coder);
}

TEST(PointwiseReject, WrongOutputSizeAndShortChunk) {
    const auto laz = vlr_with({las::LazItem{static_cast<std::uint16_t>(las::ItemType::Point10), 20, 2}});
    expect_rejected(laz, 64, 2, 30);   // output too small for two records
    expect_rejected(laz, 10, 1);       // not even the raw first record
    expect_rejected(laz, 64, 3, 40);   // output holds two records, not three
}

TEST(PointwiseReject, EmptyStreamAfterFirstPointIsTruncation) {
    const auto laz = vlr_with({las::LazItem{static_cast<std::uint16_t>(las::ItemType::Point10), 20, 2}});
    expect_rejected(laz, 20, 1000);  // raw first record, then nothing
}

}  // namespace
}  // namespace lidarscout
