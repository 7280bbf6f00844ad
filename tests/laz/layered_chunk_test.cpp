// Layered chunks (compressor 3, point formats 6-10): every corpus file the reference LASzip
// decodes gives the same point bytes (SHA-256), selective decoding gives the same fields
// while skipping the other layers, and corrupt or unsupported chunks fail cleanly.
#include <gtest/gtest.h>

#include <algorithm>

#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/sha256.hpp"
#include "dataset/tile.hpp"
#include "io/file.hpp"
#include "laz/layered_chunk.hpp"
#include "test_data.hpp"

namespace lidarscout::laz {
namespace {

using las::ItemType;

// A corpus file with layered chunks that the reference decodes.
struct LayeredFile {
    std::string name;  // the expected/ JSON name, made a valid test name
    std::string path;
    std::string sha256;
    std::uint64_t points = 0;
    int point_format = 0;
};

void PrintTo(const LayeredFile& f, std::ostream* os) { *os << f.name; }

// `text` with every character that is not a letter or digit replaced by '_' (a test name).
std::string test_name(std::string text) {
    std::replace_if(text.begin(), text.end(), [](char c) { return !std::isalnum(static_cast<unsigned char>(c)); }, '_');
    return text;
}

std::vector<LayeredFile> layered_files() {
    std::vector<LayeredFile> out;
    for (const auto& e : test::all_expected()) {
        const auto& j = *e.json;
        if (j.value("reference_result", "") != "decodes" || !j.contains("laz") || j["laz"].is_null()) continue;
        if (j["laz"].value("compressor", 0) != 3) continue;
        const std::string name = test_name(e.name.substr(0, e.name.size() - 5));
        out.push_back({name, e.file.string(), j.at("points_sha256").get<std::string>(),
                       j["header"].at("point_count").get<std::uint64_t>(), j["header"].at("point_format").get<int>()});
    }
    return out;
}

const LayeredFile& corpus_file(const std::string& part) {
    static const auto files = layered_files();
    for (const auto& f : files) {
        if (f.path.find(part) != std::string::npos) return f;
    }
    throw std::runtime_error("no layered corpus file matches " + part);
}

// A file's LASzip description, chunk list, COPC nodes (if any) and bytes.
struct LoadedFile {
    dataset::Tile tile;
    std::vector<std::uint8_t> data;

    const las::LaszipVlr& laz() const { return *tile.laz(); }
    std::size_t record() const { return laz().record_length(); }
    std::span<const std::uint8_t> bytes(const Chunk& c) const {
        return std::span<const std::uint8_t>(data).subspan(c.byte_offset, c.byte_size);
    }
};

LoadedFile load(const std::string& path) {
    auto file = io::File::open(path);
    LoadedFile f;
    f.tile = dataset::read_tile(file);
    f.data = file.read_vector(0, file.size());
    return f;
}

// Decodes every chunk with `fields` into one buffer of records (file order).
std::vector<std::uint8_t> decode_file(const LoadedFile& f, std::uint32_t fields, LayeredChunkStats* total = nullptr) {
    std::uint64_t points = 0;
    for (const auto& c : *f.tile.chunks()) points += c.point_count;
    std::vector<std::uint8_t> out(points * f.record());
    std::size_t at = 0;
    for (const auto& c : *f.tile.chunks()) {
        const std::size_t n = c.point_count * f.record();
        LayeredChunkStats stats;
        decode_layered_chunk(f.laz(), {f.bytes(c), c.point_count, std::span(out).subspan(at, n), fields}, stats);
        if (total) {
            total->layers += stats.layers;
            total->layers_decoded += stats.layers_decoded;
            total->layer_bytes += stats.layer_bytes;
            total->bytes_consumed += stats.bytes_consumed;
        }
        at += n;
    }
    return out;
}

// ---- bit-exact against the reference ------------------------------------------------------

class LayeredCorpus : public ::testing::TestWithParam<LayeredFile> {};

TEST_P(LayeredCorpus, FullDecodeMatchesReferenceSha256) {
    const auto& file = GetParam();
    const LoadedFile f = load(file.path);
    const auto records = decode_file(f, fields::kAll);
    EXPECT_EQ(records.size(), file.points * f.record());
    EXPECT_EQ(sha256_hex(records), file.sha256) << file.path;  // file order, COPC included
}

INSTANTIATE_TEST_SUITE_P(Formats, LayeredCorpus, ::testing::ValuesIn(layered_files()),
                         [](const auto& info) { return info.param.name; });

// ---- selective decoding ------------------------------------------------------------------

// The record bits (per byte) that a decode of `fields` fills in.
std::vector<std::uint8_t> wanted_bits(const las::LaszipVlr& laz, std::uint32_t want) {
    std::vector<std::uint8_t> mask(laz.record_length(), 0);
    std::size_t at = 0;
    auto set = [&](std::size_t from, std::size_t count, std::uint32_t field, std::uint8_t bits = 0xFF) {
        if (want & field) {
            for (std::size_t i = from; i < from + count; ++i) mask[at + i] |= bits;
        }
    };
    for (const auto& item : laz.items) {
        switch (static_cast<ItemType>(item.type)) {
            case ItemType::Point14:
                set(0, 12, fields::kAll);  // XYZ: always
                set(12, 2, fields::kIntensity);
                set(14, 1, fields::kReturns);
                set(15, 1, fields::kReturns, 0xF0);  // channel, scan direction, edge
                set(15, 1, fields::kClassFlags, 0x0F);
                set(16, 1, fields::kClassification);
                set(17, 1, fields::kUserData);
                set(18, 2, fields::kScanAngle);
                set(20, 2, fields::kPointSource);
                set(22, 8, fields::kGpsTime);
                break;
            case ItemType::Rgb14: set(0, 6, fields::kRgb); break;
            case ItemType::RgbNir14:
                set(0, 6, fields::kRgb);
                set(6, 2, fields::kNir);
                break;
            case ItemType::Wavepacket14: set(0, 29, fields::kWavepacket); break;
            default: set(0, item.size, fields::kExtraBytes); break;
        }
        at += item.size;
    }
    return mask;
}

class LayeredSelective : public ::testing::TestWithParam<std::string> {};

// Every single field (with XYZ) decodes to exactly the full decode's bits, all else zero.
TEST_P(LayeredSelective, EachFieldMatchesFullDecode) {
    const LoadedFile f = load(corpus_file(GetParam()).path);
    const auto full = decode_file(f, fields::kAll);
    for (std::uint32_t field = fields::kIntensity; field <= fields::kClassFlags; field <<= 1) {
        const std::uint32_t want = fields::kXyz | field;
        const auto part = decode_file(f, want);
        const auto bits = wanted_bits(f.laz(), want);
        ASSERT_EQ(part.size(), full.size());
        for (std::size_t i = 0; i < full.size(); ++i) {
            const std::uint8_t expected = full[i] & bits[i % f.record()];
            ASSERT_EQ(part[i], expected) << "field bit " << field << ", record " << i / f.record() << ", byte "
                                         << i % f.record();
        }
    }
}

// XYZ alone reads only the returns/XY and Z layers.
TEST_P(LayeredSelective, XyzOnlyDecodesTwoLayers) {
    const LoadedFile f = load(corpus_file(GetParam()).path);
    LayeredChunkStats all, xyz;
    const auto full = decode_file(f, fields::kAll, &all);
    const auto part = decode_file(f, fields::kXyz, &xyz);
    const std::size_t chunks = f.tile.chunks()->size();
    EXPECT_EQ(xyz.layers_decoded, 2 * chunks);
    EXPECT_GT(all.layers_decoded, xyz.layers_decoded);
    EXPECT_LT(xyz.bytes_consumed, all.bytes_consumed);
    EXPECT_LE(all.bytes_consumed, all.layer_bytes);
    for (std::size_t i = 0; i < full.size(); i += f.record()) {
        ASSERT_TRUE(std::equal(full.begin() + i, full.begin() + i + 12, part.begin() + i))
            << "record " << i / f.record();
    }
}

INSTANTIATE_TEST_SUITE_P(Formats, LayeredSelective,
                         ::testing::Values("pdrf10-1.4.laz", "pdrf9-1.5.laz", "pdrf7-v4-1.4.laz", "ellipsoid-1.4.laz",
                                           "77055_627755_LA93_IGN69_extra_dims", "lion_takanawa"),
                         [](const auto& info) { return test_name(info.param); });

// ---- corrupt and unsupported input -----------------------------------------------------

// Decodes `bytes` as a chunk of `points`; true if it completed, false on a lidarscout::Error.
bool try_decode(const las::LaszipVlr& laz, std::span<const std::uint8_t> bytes, std::uint64_t points) {
    std::vector<std::uint8_t> out(points * laz.record_length());
    try {
        decode_layered_chunk(laz, {bytes, points, out, fields::kAll});
        return true;
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("layered"), std::string::npos) << e.what();
        return false;
    }
}

TEST(LayeredCorrupt, TruncatedChunksAreRejected) {
    for (const char* name : {"pdrf10-1.4.laz", "1.2-with-color.copc.laz"}) {
        const LoadedFile f = load(corpus_file(name).path);
        const Chunk& c = f.tile.chunks()->back();
        const auto bytes = f.bytes(c);
        for (std::size_t cut = 0; cut < bytes.size(); cut += std::max<std::size_t>(1, bytes.size() / 97)) {
            EXPECT_FALSE(try_decode(f.laz(), bytes.first(cut), c.point_count)) << name << " cut at " << cut;
        }
        EXPECT_FALSE(try_decode(f.laz(), bytes.first(bytes.size() - 1), c.point_count));
        EXPECT_TRUE(try_decode(f.laz(), bytes, c.point_count));
    }
}

// A layer cut short (its size field lowered, its last bytes removed) fails or decodes
// something; never crashes or reads outside the chunk.
TEST(LayeredCorrupt, TruncatedLayersFailCleanly) {
    const LoadedFile f = load(corpus_file("pdrf10-1.4.laz").path);
    const Chunk& c = f.tile.chunks()->front();
    const auto bytes = f.bytes(c);
    const std::size_t sizes_at = f.record() + 4;
    const std::size_t layers = 9 + 2 + 1 + 4;  // POINT14, RGBNIR14, WAVEPACKET14, BYTE14 (4)
    int failures = 0;
    for (std::size_t layer = 0; layer < layers; ++layer) {
        std::uint32_t size;
        std::memcpy(&size, bytes.data() + sizes_at + 4 * layer, 4);
        std::size_t start = sizes_at + 4 * layers;
        for (std::size_t i = 0; i < layer; ++i) {
            std::uint32_t s;
            std::memcpy(&s, bytes.data() + sizes_at + 4 * i, 4);
            start += s;
        }
        for (std::uint32_t cut : {1u, 2u, 5u, size / 2, size}) {
            if (cut == 0 || cut > size) continue;
            std::vector<std::uint8_t> damaged(bytes.begin(), bytes.end());
            const std::uint32_t shorter = size - cut;
            std::memcpy(damaged.data() + sizes_at + 4 * layer, &shorter, 4);
            damaged.erase(damaged.begin() + static_cast<std::ptrdiff_t>(start + shorter),
                          damaged.begin() + static_cast<std::ptrdiff_t>(start + size));
            if (!try_decode(f.laz(), damaged, c.point_count)) ++failures;
        }
    }
    EXPECT_GT(failures, 0);
}

TEST(LayeredCorrupt, FlippedBytesFailCleanly) {
    std::mt19937 rng(20250611);
    int failures = 0, completions = 0;
    for (const char* name : {"pdrf10-1.4.laz", "pdrf9-1.5.laz", "pdrf7-v4-1.4.laz", "1.2-with-color.copc.laz"}) {
        const LoadedFile f = load(corpus_file(name).path);
        const Chunk& c = f.tile.chunks()->front();
        const auto bytes = f.bytes(c);
        for (int trial = 0; trial < 150; ++trial) {
            std::vector<std::uint8_t> damaged(bytes.begin(), bytes.end());
            const int flips = 1 + static_cast<int>(rng() % 4);
            for (int k = 0; k < flips; ++k) {
                damaged[rng() % damaged.size()] ^= static_cast<std::uint8_t>(1 + rng() % 255);
            }
            (try_decode(f.laz(), damaged, c.point_count) ? completions : failures)++;
        }
    }
    std::printf("flipped bytes: %d decodes failed cleanly, %d completed\n", failures, completions);
    EXPECT_GT(failures, 0);
}

TEST(LayeredUnsupported, ItemListsOutsideTheFormatAreRejected) {
    const LoadedFile f = load(corpus_file("pdrf10-1.4.laz").path);
    const Chunk& c = f.tile.chunks()->front();
    auto rejects = [&](las::LaszipVlr laz) { return !try_decode(laz, f.bytes(c), c.point_count); };

    las::LaszipVlr laz = f.laz();
    EXPECT_TRUE(try_decode(laz, f.bytes(c), c.point_count));
    laz.compressor = 2;
    EXPECT_TRUE(rejects(laz));
    laz = f.laz();
    laz.items[0].type = static_cast<std::uint16_t>(ItemType::Point10);
    EXPECT_TRUE(rejects(laz));
    laz = f.laz();
    std::swap(laz.items[0], laz.items[1]);
    EXPECT_TRUE(rejects(laz));
    laz = f.laz();
    laz.items[2].version = 2;  // WAVEPACKET14 exists only in versions 3 and 4
    EXPECT_TRUE(rejects(laz));
    laz = f.laz();
    laz.items[1].version = 5;
    EXPECT_TRUE(rejects(laz));
    laz = f.laz();
    laz.items[1].size = 6;  // RGBNIR14 is 8 bytes
    EXPECT_TRUE(rejects(laz));

    std::vector<std::uint8_t> small(f.record());
    EXPECT_THROW(decode_layered_chunk(f.laz(), {f.bytes(c), c.point_count, small, fields::kAll}), Error);
}

}  // namespace
}  // namespace lidarscout::laz
