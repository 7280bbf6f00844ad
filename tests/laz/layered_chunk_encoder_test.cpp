// The layered chunk encoder (compressor 3, POINT14/RGB14/RGBNIR14/WAVEPACKET14/BYTE14 version 3):
// - bit-exactness: the point14 pairs of formats/expected/encode_pairs.json (LAS 1.4 formats
//   6 and 8, chunks of 256) re-encode to the LAZ's chunk bytes exactly;
// - losslessness: every LAS file of format 6-10 in formats/, a Kentucky survey tile converted
//   to format 7, and hand-made records (all four scanner channels, return numbers and GPS
//   times of every kind, wave packets of every kind, extra bytes) come back unchanged through
//   encode -> decode (the LAZ files with wave packets that LASzip wrote are reproduced byte for
//   byte in chunk_encoder_test.cpp);
// - constant fields give empty layers; bad item lists and sizes are rejected.
#include <gtest/gtest.h>

#include <algorithm>
#include <ctime>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "dataset/tile.hpp"
#include "io/file.hpp"
#include "las/header.hpp"
#include "las/laszip_vlr.hpp"
#include "las/point_format.hpp"
#include "laz/chunk_decoder.hpp"
#include "laz/layered_chunk.hpp"
#include "laz/layered_chunk_encoder.hpp"
#include "laz/laszip_vlr_writer.hpp"
#include "laz/chunk_codec_helpers.hpp"
#include "test_data.hpp"

namespace lidarscout::laz {
namespace {

namespace fs = std::filesystem;
using namespace codec_test;

void expect_round_trip(const las::LaszipVlr& laz, std::span<const std::uint8_t> records, std::uint64_t chunk_size,
                       const std::string& what) {
    const Encoded e = encode_in_chunks(laz, records, chunk_size);
    EXPECT_EQ(first_difference(decode_chunks(laz, e), records, laz.record_length()), -1)
        << what << ", chunks of " << chunk_size;
}

std::vector<std::uint8_t> las_records(const io::File& file, const dataset::Tile& tile) {
    return file.read_vector(tile.header.offset_to_point_data, tile.header.point_count * tile.header.record_length,
                            "point records");
}

// ---- bit-exactness on the point14 encode pairs ---------------------------------------------

struct Pair {
    fs::path las;
    fs::path laz;
    std::uint32_t chunk_size = 0;
};

std::vector<Pair> point14_pairs() {
    std::vector<Pair> pairs;
    for (const auto& j : test::read_json(test::formats_dir() / "expected" / "encode_pairs.json")) {
        Pair p{test::formats_dir() / j.at("las").get<std::string>(),
               test::formats_dir() / j.at("laz").get<std::string>(), j.at("chunk_size").get<std::uint32_t>()};
        const auto file = io::File::open(p.las.string());
        if (dataset::read_tile(file).header.point_format >= 6) pairs.push_back(p);
    }
    return pairs;
}

TEST(LayeredEncode, PairsAreByteIdenticalChunkByChunk) {
    const auto pairs = point14_pairs();
    // pdrf6 and pdrf8 (chunks of 256) and test1_4 -> 1_4_w_evlr (format 6, chunks of 50000).
    ASSERT_GE(pairs.size(), 3u) << "the encode pairs of formats 6-8";
    std::size_t chunks = 0;
    for (const Pair& pair : pairs) {
        SCOPED_TRACE(pair.laz.filename().string());
        const auto las_file = io::File::open(pair.las.string());
        const auto laz_file = io::File::open(pair.laz.string());
        const auto las_tile = dataset::read_tile(las_file);
        const auto laz_tile = dataset::read_tile(laz_file);
        const las::LaszipVlr laz =
            make_laszip_vlr(las_tile.header.point_format, las_tile.header.record_length, pair.chunk_size);
        ASSERT_EQ(laz.compressor, 3);
        ASSERT_EQ(laz.items.size(), laz_tile.laz()->items.size());
        const auto records = las_records(las_file, las_tile);
        const auto& stored_chunks = laz_tile.chunks().value().chunks();
        const Encoded ours = encode_in_chunks(laz, records, pair.chunk_size);
        ASSERT_EQ(ours.chunks.size(), stored_chunks.size());
        chunks += ours.chunks.size();
        for (std::size_t i = 0; i < ours.chunks.size(); ++i) {
            const Chunk& c = stored_chunks[i];
            ASSERT_EQ(ours.chunks[i].point_count, c.point_count) << "chunk " << i;
            const auto stored = laz_file.read_vector(c.byte_offset, c.byte_size, "chunk");
            const auto mine = std::span(ours.bytes).subspan(ours.chunks[i].byte_offset, ours.chunks[i].byte_size);
            EXPECT_TRUE(std::equal(mine.begin(), mine.end(), stored.begin(), stored.end()))
                << "chunk " << i << ": " << mine.size() << " bytes encoded, " << stored.size()
                << " stored, first difference at byte "
                << (std::mismatch(mine.begin(), mine.end(), stored.begin(), stored.end()).first - mine.begin());
        }
    }
    EXPECT_GE(chunks, 5u);  // the pdrf files span several chunks of 256
}

// ---- losslessness ----------------------------------------------------------------------

TEST(LayeredEncode, EveryPoint14LasFileRoundTrips) {
    std::size_t files = 0;
    for (const auto& e : test::all_expected()) {
        const auto& h = e.json->at("header");
        if (h.is_null() || h.at("compressed").get<bool>()) continue;
        const int format = h.at("point_format").get<int>();
        if (format < 6 || e.json->at("reference_result") != "decodes") continue;
        const auto file = io::File::open(e.file.string());
        const auto tile = dataset::read_tile(file);
        if (tile.header.point_count == 0) continue;
        const auto laz = make_laszip_vlr(tile.header.point_format, tile.header.record_length, 50000);
        const auto records = las_records(file, tile);
        expect_round_trip(laz, records, 50000, e.name);
        const std::size_t few = std::min<std::size_t>(tile.header.point_count, 300) * tile.header.record_length;
        for (std::uint64_t size : {1u, 2u, 7u, 100u}) {
            expect_round_trip(laz, std::span(records).first(few), size, e.name);
        }
        ++files;
    }
    EXPECT_GE(files, 20u);  // 16 of formats 6-8, pdrf9 and pdrf10 (1.4 and 1.5)
}

// A Kentucky tile (format 3) converted to format 7: round trip, and the single-thread speed.
TEST(LayeredEncode, SurveyTileAsFormat7RoundTrips) {
    const fs::path path = test::surveys_dir() / "ky-red-river-gorge" / "N105E348.laz";
    const auto file = io::File::open(path.string());
    const auto tile = dataset::read_tile(file);
    const auto& chunks = tile.chunks().value().chunks();
    const std::size_t in_rl = tile.header.record_length;
    // The first few chunks (about 200,000 points) are plenty.
    const std::size_t take = std::min<std::size_t>(chunks.size(), 4);
    std::uint64_t points = 0;
    for (std::size_t i = 0; i < take; ++i) points += chunks[i].point_count;
    std::vector<std::uint8_t> records(points * in_rl);
    for (std::size_t i = 0; i < take; ++i) {
        const Chunk& c = chunks[i];
        const auto stored = file.read_vector(c.byte_offset, c.byte_size, "chunk");
        decode_chunk(*tile.laz(),
                     {stored, c.point_count, std::span(records).subspan(c.first_point * in_rl, c.point_count * in_rl)});
    }
    const auto& f7 = las::point_format_info(7);
    std::vector<std::uint8_t> converted(points * f7.size);
    las::convert_records(records, las::point_format_info(tile.header.point_format), static_cast<std::uint16_t>(in_rl),
                         converted, f7, f7.size, tile.header);
    const auto laz = make_laszip_vlr(7, f7.size, 50000);

    // Thread CPU time: what one core spends, whatever else the machine runs.
    const auto cpu_seconds = [] {
        timespec ts{};
        clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
        return static_cast<double>(ts.tv_sec) + static_cast<double>(ts.tv_nsec) * 1e-9;
    };
    const double t0 = cpu_seconds();
    const Encoded e = encode_in_chunks(laz, converted, 50000);
    const double seconds = cpu_seconds() - t0;
    std::cout << "[ layered encode ] " << points << " format-7 points in " << seconds << " s of CPU: "
              << static_cast<double>(points) / seconds / 1e6 << " M points/s, " << e.bytes.size() << " bytes ("
              << static_cast<double>(e.bytes.size()) / static_cast<double>(converted.size()) * 100 << "% of LAS)\n";
    EXPECT_EQ(first_difference(decode_chunks(laz, e), converted, f7.size), -1);
    EXPECT_LT(e.bytes.size(), converted.size() / 3);
}

// Hand-made records of format 8 with 3 extra bytes: runs on all four scanner channels
// (with new channels appearing mid-chunk), return numbers that stay, step by one or jump
// (also out of spec), numbers of returns that change, GPS times that stay, advance by
// multiples of the last step, jump to old or new sequences; every other attribute
// changing now and then.
constexpr std::size_t kHandRl = 38 + 3;

std::vector<std::uint8_t> hand_made_records(std::size_t n, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::vector<std::uint8_t> out(n * kHandRl);
    const auto sometimes = [&](unsigned one_in) { return rng() % one_in == 0; };
    struct Channel {
        std::int32_t x = 1000, y = -2000, z = 50;
        double times[6] = {100.0, 2.0e8, -4.0e5, 3.0e11, 17.0, 9.0e9};
        int seq = 0;
        double step = 2.0e-5;
        std::uint8_t r = 1, n = 1;
    };
    std::array<Channel, 4> channels;
    std::uint32_t channel = 2;
    std::uint16_t intensity = 300, source = 9, rgb[4] = {500, 500, 500, 7};
    std::int16_t angle = 0;
    std::uint8_t cls = 2, flags = 0, user = 0, extra[3] = {1, 2, 3};
    for (std::size_t i = 0; i < n; ++i) {
        if (sometimes(25)) channel = rng() % 4;
        Channel& c = channels[channel];
        c.x += static_cast<std::int32_t>(rng() % 2001) - 1000;
        const std::uint32_t dy = sometimes(50) ? rng() : static_cast<std::uint32_t>(rng() % 301) - 150u;
        c.y = static_cast<std::int32_t>(static_cast<std::uint32_t>(c.y) + dy);  // wraps, like the coder
        c.z = static_cast<std::int32_t>(sometimes(40) ? rng() : static_cast<std::uint32_t>(c.z) + rng() % 41 - 20u);
        const unsigned rk = rng() % 10;
        bool new_pulse = false;
        if (rk < 4) {
            if (c.r < c.n) ++c.r; else { c.r = 1; new_pulse = true; }
        } else if (rk < 6) {
            c.n = static_cast<std::uint8_t>(1 + rng() % 5);
            c.r = 1;
            new_pulse = true;
        } else if (rk == 6) {
            c.r = static_cast<std::uint8_t>(rng() % 16);  // any jump, also out of spec
            c.n = static_cast<std::uint8_t>(rng() % 16);
        } else if (rk == 7 && c.r > 1) {
            --c.r;
        }
        const unsigned t = rng() % 100;
        if (t < 5) {
            c.seq = static_cast<int>(rng() % 6);
        } else if (t < 9) {
            c.step *= (sometimes(2) ? 1 : -1) * static_cast<double>(1 + rng() % 700);
        } else if (t < 11) {
            c.step = 1.0e-5 * (1 + rng() % 3);
        } else if (t < 12) {
            c.times[c.seq] = std::ldexp(static_cast<double>(rng()), static_cast<int>(rng() % 60) - 20);
        }
        if (new_pulse || t < 12) c.times[c.seq] += c.step;
        if (sometimes(3)) intensity = static_cast<std::uint16_t>(sometimes(5) ? rng() : intensity + rng() % 21 - 10);
        if (sometimes(12)) cls = static_cast<std::uint8_t>(rng());
        if (sometimes(15)) flags = static_cast<std::uint8_t>(rng() & 0xCF);  // the channel bits are set below
        if (sometimes(9)) angle = static_cast<std::int16_t>(sometimes(4) ? rng() : angle + rng() % 61 - 30);
        if (sometimes(20)) user = static_cast<std::uint8_t>(rng());
        if (sometimes(30)) source = static_cast<std::uint16_t>(rng());
        if (sometimes(4)) {
            if (sometimes(4)) {
                rgb[0] = rgb[1] = rgb[2] = static_cast<std::uint16_t>(rng());
            } else {
                for (int k = 0; k < 3; ++k) {
                    rgb[k] = static_cast<std::uint16_t>(sometimes(3) ? rng() : rgb[k] + rng() % 11 - 5);
                }
            }
        }
        if (sometimes(6)) rgb[3] = static_cast<std::uint16_t>(sometimes(2) ? rng() : rgb[3] + 1);
        if (sometimes(5)) extra[rng() % 3] = static_cast<std::uint8_t>(rng());

        std::uint8_t* r = out.data() + i * kHandRl;
        std::memcpy(r + 0, &c.x, 4);
        std::memcpy(r + 4, &c.y, 4);
        std::memcpy(r + 8, &c.z, 4);
        std::memcpy(r + 12, &intensity, 2);
        r[14] = static_cast<std::uint8_t>(c.r | (c.n << 4));
        r[15] = static_cast<std::uint8_t>(flags | (channel << 4));
        r[16] = cls;
        r[17] = user;
        std::memcpy(r + 18, &angle, 2);
        std::memcpy(r + 20, &source, 2);
        std::memcpy(r + 22, &c.times[c.seq], 8);
        std::memcpy(r + 30, rgb, 8);
        std::memcpy(r + 38, extra, 3);
    }
    return out;
}

TEST(LayeredEncode, HandMadeChannelsReturnsAndTimesRoundTrip) {
    const auto records = hand_made_records(6000, 11);
    // The records do use all four channels and several return kinds.
    std::array<std::size_t, 4> per_channel{};
    for (std::size_t i = 0; i < 6000; ++i) ++per_channel[(records[i * kHandRl + 15] >> 4) & 3];
    for (std::size_t n : per_channel) EXPECT_GT(n, 500u);

    const auto f8 = make_laszip_vlr(8, kHandRl, 50000);
    for (std::uint64_t size : {1u, 2u, 3u, 50u, 256u, 6000u}) {
        expect_round_trip(f8, records, size, "format 8 + 3 bytes");
    }

    // The same points as formats 6 and 7 (with and without extra bytes).
    for (std::uint8_t format : {6, 7}) {
        const auto& info = las::point_format_info(format);
        std::vector<std::uint8_t> cut(6000 * info.size);
        for (std::size_t i = 0; i < 6000; ++i) {
            std::memcpy(cut.data() + i * info.size, records.data() + i * kHandRl, info.size);
        }
        expect_round_trip(make_laszip_vlr(format, info.size, 50000), cut, 1000, "format " + std::to_string(format));
    }
    const auto with_extra = make_laszip_vlr(8, kHandRl, 50000);
    expect_round_trip(with_extra, hand_made_records(3000, 12), 777, "second seed");
}

// The hand-made records as formats 10 (format 8's 38 bytes, the packet, 3 extra bytes) and 9
// (without colour), their wave packets of every kind (wave_packets) switching contexts with the
// scanner channel.
TEST(LayeredEncode, HandMadeWavePacketsRoundTrip) {
    constexpr std::size_t kPoints = 6000;
    const auto records = hand_made_records(kPoints, 13);
    const auto packets = wave_packets(kPoints, 14);
    const auto f10 = with_wave_packets(records, kHandRl, 38, packets);
    std::vector<std::uint8_t> no_rgb;
    for (std::size_t i = 0; i < kPoints; ++i) {
        const std::uint8_t* r = records.data() + i * kHandRl;
        no_rgb.insert(no_rgb.end(), r, r + 30);
        no_rgb.insert(no_rgb.end(), r + 38, r + kHandRl);
    }
    const auto f9 = with_wave_packets(no_rgb, 33, 30, packets);
    for (const auto& [format, cut] : {std::pair{std::uint8_t{10}, f10}, std::pair{std::uint8_t{9}, f9}}) {
        const std::size_t rl = cut.size() / kPoints;
        const auto laz = make_laszip_vlr(format, static_cast<std::uint16_t>(rl), 50000);
        for (std::uint64_t size : {1u, 3u, 256u, 6000u}) {
            expect_round_trip(laz, cut, size, "format " + std::to_string(format));
        }
    }
}

// A layer whose field never changes is stored empty (as LASzip does), and still decodes.
TEST(LayeredEncode, ConstantFieldsGiveEmptyLayers) {
    auto records = hand_made_records(500, 5);
    for (std::size_t i = 0; i < 500; ++i) {
        std::uint8_t* r = records.data() + i * kHandRl;
        r[15] = 0;   // channel 0, no flags
        r[16] = 6;   // classification
        std::memset(r + 18, 0, 2);  // scan angle
        std::memset(r + 30, 0, 8);  // grey black colour and NIR 0
        r[39] = 42;  // second extra byte
    }
    const auto laz = make_laszip_vlr(8, kHandRl, 50000);
    const Encoded e = encode_in_chunks(laz, records, 500);
    ASSERT_EQ(e.chunks.size(), 1u);
    // Layers: 9 of POINT14, RGB, NIR, 3 bytes.
    std::array<std::uint32_t, 14> sizes{};
    std::memcpy(sizes.data(), e.bytes.data() + kHandRl + 4, sizeof sizes);
    std::uint32_t count = 0;
    std::memcpy(&count, e.bytes.data() + kHandRl, 4);
    EXPECT_EQ(count, 500u);
    EXPECT_GT(sizes[0], 0u);   // returns/XY
    EXPECT_GT(sizes[1], 0u);   // Z
    EXPECT_EQ(sizes[2], 0u);   // classification
    EXPECT_EQ(sizes[3], 0u);   // flags
    EXPECT_GT(sizes[4], 0u);   // intensity
    EXPECT_EQ(sizes[5], 0u);   // scan angle
    EXPECT_GT(sizes[8], 0u);   // GPS time
    EXPECT_EQ(sizes[9], 0u);   // RGB
    EXPECT_EQ(sizes[10], 0u);  // NIR
    EXPECT_GT(sizes[11], 0u);
    EXPECT_EQ(sizes[12], 0u);
    EXPECT_GT(sizes[13], 0u);
    std::uint64_t total = kHandRl + 4 + sizeof sizes;
    for (auto s : sizes) total += s;
    EXPECT_EQ(total, e.bytes.size());
    EXPECT_EQ(first_difference(decode_chunks(laz, e), records, kHandRl), -1);
}

TEST(LayeredEncode, RejectsWhatItCannotWrite) {
    const auto ok = make_laszip_vlr(7, 36, 50000);
    std::vector<std::uint8_t> records(36 * 3);
    std::vector<std::uint8_t> out;
    EXPECT_NO_THROW(encode_layered_chunk(ok, records, 3, out));
    EXPECT_THROW(encode_layered_chunk(ok, records, 2, out), Error);  // size mismatch
    EXPECT_THROW(encode_layered_chunk(ok, records, 0, out), Error);
    auto v4 = ok;
    v4.items[0].version = 4;
    EXPECT_THROW(encode_layered_chunk(v4, records, 3, out), Error);
    auto wave = make_laszip_vlr(9, 59, 50000);
    std::vector<std::uint8_t> wave_records(59 * 2);
    EXPECT_NO_THROW(encode_layered_chunk(wave, wave_records, 2, out));
    wave.items[1].size = 28;
    EXPECT_THROW(encode_layered_chunk(wave, std::span(wave_records).first(58 * 2), 2, out), Error);
    EXPECT_THROW(encode_layered_chunk(make_laszip_vlr(3, 34, 50000), std::vector<std::uint8_t>(34), 1, out), Error);
}

}  // namespace
}  // namespace lidarscout::laz
