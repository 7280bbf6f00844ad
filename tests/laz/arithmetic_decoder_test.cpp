// The arithmetic decoder and its adaptive models: hand-computed model states, a real LASzip
// stream (a COPC chunk table) decoded bit-exactly, round trips through a test encoder for
// every kind of read, and safe behaviour on truncated or corrupt streams.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "core/error.hpp"
#include "laz/arithmetic_decoder.hpp"
#include "laz/arithmetic_models.hpp"
#include "laz/integer_decompressor.hpp"
#include "laz/test_arithmetic_encoder.hpp"

namespace lidarscout::laz {
namespace {

using test::TestEncoder;

// ---- models: states computed by hand from the update rules ------------------------------

TEST(ArithBitModel, StartsEquiprobable) {
    BitModel m;
    EXPECT_EQ(m.zero_probability(), 4096u);  // 1/2 in 13-bit fixed point
}

TEST(ArithBitModel, FirstUpdateAfterFourBits) {
    BitModel m;
    for (int i = 0; i < 3; ++i) m.record(0);
    EXPECT_EQ(m.zero_probability(), 4096u);  // not yet re-estimated
    m.record(0);
    // counts: 5 zeros of 6; p0 = (5 * (2^31 / 6)) >> 18
    EXPECT_EQ(m.zero_probability(), (5u * (0x80000000u / 6u)) >> 18);
    // next update after 5 more bits: 5 ones -> 5 zeros of 11
    for (int i = 0; i < 5; ++i) m.record(1);
    EXPECT_EQ(m.zero_probability(), (5u * (0x80000000u / 11u)) >> 18);
}

TEST(ArithBitModel, ResetRestoresStartState) {
    BitModel m;
    for (int i = 0; i < 100; ++i) m.record(1);
    EXPECT_LT(m.zero_probability(), 1000u);
    m.reset();
    EXPECT_EQ(m.zero_probability(), 4096u);
}

TEST(ArithBitModel, ProbabilityStaysInsideTheOpenInterval) {
    BitModel zeros, ones;
    for (int i = 0; i < 100000; ++i) {
        zeros.record(0);
        ones.record(1);
    }
    EXPECT_LT(zeros.zero_probability(), 8192u);
    EXPECT_GT(ones.zero_probability(), 0u);
}

TEST(ArithSymbolModel, StartsUniform) {
    SymbolModel m(4);
    EXPECT_EQ(m.symbols(), 4u);
    EXPECT_FALSE(m.has_lookup());
    for (std::uint32_t s = 0; s < 4; ++s) EXPECT_EQ(m.cdf(s), s * 8192u);
}

TEST(ArithSymbolModel, FirstUpdateAfterHalfTheAlphabetPlusThree) {
    SymbolModel m(4);
    for (int i = 0; i < 4; ++i) m.record(0);
    EXPECT_EQ(m.cdf(1), 8192u);  // (4 + 6) / 2 = 5 symbols before the first update
    m.record(0);
    // counts 6,1,1,1 (total 9): cdf = (2^31 / 9) * partial sum >> 16
    const std::uint32_t scale = 0x80000000u / 9u;
    EXPECT_EQ(m.cdf(0), 0u);
    EXPECT_EQ(m.cdf(1), (scale * 6u) >> 16);
    EXPECT_EQ(m.cdf(2), (scale * 7u) >> 16);
    EXPECT_EQ(m.cdf(3), (scale * 8u) >> 16);
}

TEST(ArithSymbolModel, LargeAlphabetsGetALookupTable) {
    EXPECT_FALSE(SymbolModel(16).has_lookup());
    SymbolModel m17(17);
    ASSERT_TRUE(m17.has_lookup());
    EXPECT_EQ(m17.lookup_size(), 32u);  // about one entry per symbol: 2^5 >= 17
    EXPECT_EQ(m17.lookup_shift(), 10u);
    SymbolModel m256(256);
    EXPECT_EQ(m256.lookup_size(), 256u);  // 2^8 = 256
    // Uniform 256 symbols: slot j holds symbol j; entry j (j >= 1) is the last symbol below
    // slot j, and the two entries past the slots are the last symbol.
    EXPECT_EQ(m256.lookup()[0], 0u);
    EXPECT_EQ(m256.lookup()[1], 0u);
    EXPECT_EQ(m256.lookup()[64], 63u);
    EXPECT_EQ(m256.lookup()[255], 254u);
    EXPECT_EQ(m256.lookup()[256], 255u);
    EXPECT_EQ(m256.lookup()[257], 255u);
}

// Entry j (j >= 1) of the lookup table is the last symbol whose interval starts below slot j
// (its cdf below j << shift), entry 0 symbol 0: checked against that definition, symbol by
// symbol, for skewed distributions of several alphabets at many points of their update schedule.
TEST(ArithSymbolModel, LookupEntriesAreTheLastSymbolStartingBelowTheirSlot) {
    std::mt19937 rng(7);
    for (std::uint32_t symbols : {17u, 33u, 64u, 256u, 516u, kMaxSymbols}) {
        SymbolModel m(symbols);
        for (int step = 0; step < 30; ++step) {
            for (int i = 0; i < 400; ++i) m.record(rng() % (1 + rng() % symbols));  // skews the counts
            ASSERT_EQ(m.lookup()[0], 0u);
            for (std::uint32_t j = 1; j <= m.lookup_size() + 1; ++j) {
                std::uint32_t last = 0;
                for (std::uint32_t s = 0; s < symbols; ++s) {
                    if (m.cdf(s) < (j << m.lookup_shift())) last = s;
                }
                ASSERT_EQ(m.lookup()[j], last) << symbols << " symbols, entry " << j << ", step " << step;
            }
        }
    }
}

// The tables hold 16-bit entries: a symbol coded over and over (a constant field) must keep
// nearly the whole range, at every point of its update schedule (a count that wrapped would
// collapse it), in the smallest and the largest alphabets.
TEST(ArithSymbolModel, OneSymbolCodedMillionsOfTimesKeepsTheRange) {
    for (std::uint32_t symbols : {2u, 16u, 17u, 256u, kMaxSymbols}) {
        SymbolModel m(symbols);
        for (int i = 0; i < 3'000'000; ++i) {
            m.record(0);
            if (i > 200'000) {
                ASSERT_GT(m.cdf(1), 3u * kSymbolCountLimit / 4) << symbols << " symbols, record " << i;
            }
        }
        EXPECT_EQ(m.cdf(0), 0u);
    }
}

// The small-alphabet search multiplies instead of dividing: it must pick the same symbol as
// counting cdf(s) <= value / length for every code value and interval length the decoder can
// hold (length < 2^17), including skewed distributions and corrupt values beyond the interval.
std::uint32_t count_by_division(const SymbolModel& m, std::uint32_t value, std::uint32_t length) {
    std::uint32_t s = 0;
    for (std::uint32_t i = 1; i < m.symbols(); ++i) s += m.cdf(i) <= value / length ? 1u : 0u;
    return s;
}

TEST(ArithSymbolModel, SmallAlphabetSearchMatchesDivision) {
    std::mt19937 rng(32);
    const std::uint32_t kLongest = 0xFFFFFFFFu >> kSymbolProbabilityBits;
    for (std::uint32_t symbols = 2; symbols <= 16; ++symbols) {
        SymbolModel m(symbols);
        for (int step = 0; step < 40; ++step) {
            for (int i = 0; i < 50; ++i) m.record(rng() % (1 + rng() % symbols));  // skews the counts
            for (std::uint32_t length : {1u << 9, (1u << 9) + 1, kLongest - 1, kLongest}) {
                for (std::uint32_t s = 0; s < symbols; ++s) {  // both sides of every boundary
                    const std::uint32_t edge = m.cdf(s) * length;
                    for (std::uint32_t value : {edge, edge - 1, edge + 1, edge + length - 1}) {
                        ASSERT_EQ(m.last_at_or_below(value, length), count_by_division(m, value, length));
                    }
                }
                ASSERT_EQ(m.last_at_or_below(0xFFFFFFFFu, length), count_by_division(m, 0xFFFFFFFFu, length));
            }
            for (int i = 0; i < 2000; ++i) {
                const std::uint32_t length = (1u << 9) + rng() % (kLongest - (1u << 9) + 1);
                const std::uint32_t value = rng();
                ASSERT_EQ(m.last_at_or_below(value, length), count_by_division(m, value, length));
            }
        }
    }
}

// The guess is the symbol of the largest count when that count is at least half the total, with
// its interval in cdf units; otherwise an empty interval.
TEST(ArithSymbolModel, GuessIsTheSymbolHoldingHalfTheCounts) {
    SymbolModel m(17);
    EXPECT_EQ(m.guess().low, m.guess().high);  // uniform: nothing to guess
    EXPECT_FALSE(m.guess().last);
    for (int i = 0; i < 200; ++i) m.record(5);
    EXPECT_EQ(m.guess().symbol, 5u);
    EXPECT_EQ(m.guess().low, m.cdf(5));
    EXPECT_EQ(m.guess().high, m.cdf(6));
    EXPECT_GT(m.cdf(6) - m.cdf(5), 1u << 14);  // it does hold half
    EXPECT_FALSE(m.guess().last);
    for (int i = 0; i < 2000; ++i) m.record(16);
    EXPECT_EQ(m.guess().symbol, 16u);
    EXPECT_EQ(m.guess().low, m.cdf(16));
    EXPECT_TRUE(m.guess().last);
    for (std::uint32_t s = 0; s < 17 * 400; ++s) m.record(s % 17);  // counts even out below half
    EXPECT_EQ(m.guess().low, m.guess().high);
    EXPECT_FALSE(m.guess().last);
}

TEST(ArithSymbolModel, RejectsImpossibleAlphabets) {
    EXPECT_THROW(SymbolModel{1}, Error);
    EXPECT_THROW(SymbolModel{kMaxSymbols + 1}, Error);
    EXPECT_NO_THROW(SymbolModel{kMaxSymbols});
}

// ---- a real stream: the chunk table of PDAL's lone-star.copc.laz (written by LASzip) ------

// The 83 coded bytes after the table's version and count (15 chunks, variable size).
const std::vector<std::uint8_t> kLoneStarTable = {
    0x44, 0x75, 0x1d, 0x7f, 0x75, 0x24, 0x05, 0x45, 0x84, 0x02, 0x7b, 0x1e, 0xef, 0x6e, 0xb5, 0x71,
    0xa9, 0xb3, 0x24, 0x6b, 0x8b, 0xeb, 0x8e, 0x78, 0x15, 0xde, 0x52, 0x8f, 0xc3, 0x49, 0xbf, 0xd3,
    0x96, 0xd4, 0xf3, 0x57, 0x7a, 0xe1, 0x40, 0x13, 0x4c, 0x29, 0xe4, 0x26, 0xae, 0x74, 0x1c, 0xc7,
    0x9d, 0x1d, 0x8f, 0x43, 0xe2, 0xd6, 0x9c, 0xcb, 0x1b, 0xec, 0x96, 0x3f, 0x9a, 0xeb, 0xce, 0x65,
    0xca, 0x03, 0x1e, 0x6b, 0xd3, 0x90, 0x10, 0x6b, 0xd4, 0xd3, 0x59, 0xfb, 0xf0, 0x6f, 0x82, 0x53,
    0x00, 0x00, 0x00};
// (points, bytes) per chunk, as LASzip reports them.
const std::vector<std::pair<int, int>> kLoneStarChunks = {
    {212, 1438},     {42862, 202277}, {30018, 141467}, {11135, 50154},  {126731, 585499},
    {5885, 27975},   {54282, 251691}, {24696, 116124}, {58730, 263163}, {318, 1733},
    {58393, 431475}, {32909, 159695}, {30657, 146833}, {8387, 64716},   {33647, 259054}};

std::vector<std::pair<int, int>> decode_table(std::span<const std::uint8_t> bytes, std::size_t count,
                                              ArithmeticDecoder& dec) {
    dec.start(bytes);
    IntegerDecompressor ic(32, 2);
    std::vector<std::pair<int, int>> out;
    int points = 0, size = 0;
    for (std::size_t i = 0; i < count; ++i) {
        points = ic.decompress(dec, points, 0);
        size = ic.decompress(dec, size, 1);
        out.emplace_back(points, size);
    }
    return out;
}

TEST(ArithDecoder, DecodesARealLaszipStreamBitExactly) {
    ArithmeticDecoder dec;
    EXPECT_EQ(decode_table(kLoneStarTable, kLoneStarChunks.size(), dec), kLoneStarChunks);
    EXPECT_EQ(dec.bytes_consumed(), kLoneStarTable.size());  // in sync with the writer
    EXPECT_EQ(dec.overrun(), 0u);
}

TEST(ArithDecoder, MissingTrailingZerosAreMadeUp) {
    // The writer's last three bytes are zeros; without them the result is the same and the
    // decoder reports the three bytes it made up.
    std::span<const std::uint8_t> cut(kLoneStarTable.data(), kLoneStarTable.size() - 3);
    ArithmeticDecoder dec;
    EXPECT_EQ(decode_table(cut, kLoneStarChunks.size(), dec), kLoneStarChunks);
    EXPECT_EQ(dec.overrun(), 3u);
}

TEST(ArithDecoder, AFlippedBitChangesTheResult) {
    auto bytes = kLoneStarTable;
    bytes[10] ^= 0x10;
    ArithmeticDecoder dec;
    EXPECT_NE(decode_table(bytes, kLoneStarChunks.size(), dec), kLoneStarChunks);
}

// ---- round trips through the test encoder -------------------------------------------------

TEST(ArithDecoder, RoundTripsBitsUnderAModel) {
    std::mt19937 rng(1);
    std::bernoulli_distribution skewed(0.2);
    std::vector<std::uint32_t> bits(20000);
    for (auto& b : bits) b = skewed(rng);
    TestEncoder enc;
    BitModel em;
    for (auto b : bits) enc.encode_bit(em, b);
    const auto stream = enc.finish();
    EXPECT_LT(stream.size(), bits.size() / 8);  // a skewed source compresses

    ArithmeticDecoder dec(stream);
    BitModel dm;
    for (std::size_t i = 0; i < bits.size(); ++i) ASSERT_EQ(dec.decode_bit(dm), bits[i]) << "bit " << i;
    EXPECT_EQ(dec.bytes_consumed(), stream.size());
    EXPECT_EQ(dec.overrun(), 0u);
}

class ArithSymbolRoundTrip : public ::testing::TestWithParam<std::uint32_t> {};

// `symbols` coded under one adaptive model of `n` symbols.
std::vector<std::uint8_t> encode_symbols(std::uint32_t n, const std::vector<std::uint32_t>& symbols) {
    TestEncoder enc;
    SymbolModel em(n);
    for (auto s : symbols) enc.encode_symbol(em, s);
    return enc.finish();
}

TEST_P(ArithSymbolRoundTrip, DecodesWhatWasEncoded) {
    const std::uint32_t n = GetParam();
    std::mt19937 rng(n);
    std::geometric_distribution<std::uint32_t> skewed(0.3);  // favours small symbols
    std::vector<std::uint32_t> symbols(30000);
    for (auto& s : symbols) s = std::min(skewed(rng), n - 1);
    symbols[7] = n - 1;  // the last symbol takes the other branch
    const auto stream = encode_symbols(n, symbols);

    ArithmeticDecoder dec(stream);
    SymbolModel dm(n);
    for (std::size_t i = 0; i < symbols.size(); ++i) ASSERT_EQ(dec.decode_symbol(dm), symbols[i]) << "symbol " << i;
    EXPECT_EQ(dec.bytes_consumed(), stream.size());
}

// The guess tested first: a source whose most frequent symbol moves from 1 to the last one (whose
// interval runs to the end of the length) and then holds about half the counts (so the guess comes
// and goes, also at updates right after it was taken), decoded with and without the guess from the
// same models, symbol by symbol.
TEST_P(ArithSymbolRoundTrip, LikelySymbolDecodesWhatWasEncoded) {
    const std::uint32_t n = GetParam();
    std::mt19937 rng(n + 1);
    std::uniform_int_distribution<std::uint32_t> any(0, n - 1);
    std::bernoulli_distribution usual(0.8), half(0.5 * (n - 2) / (n - 1));  // a share of 1/2 for 1
    std::vector<std::uint32_t> symbols(70000);
    for (std::size_t i = 0; i < symbols.size(); ++i) {
        if (i < 40000) symbols[i] = usual(rng) ? (i < 10000 ? 1 : n - 1) : any(rng);
        else symbols[i] = half(rng) ? 1 : any(rng);  // about half: the guess comes and goes at updates
    }
    // The first update comes after (n + 6) / 2 symbols; models of 2 and 3 symbols start with a guess
    // of 0. Taking it at the update that moves the guess to the last symbol must still give 0.
    const std::uint32_t first_update = (n + 6) / 2;
    std::fill(symbols.begin(), symbols.begin() + first_update - 1, n - 1);
    symbols[first_update - 1] = 0;
    const auto stream = encode_symbols(n, symbols);

    ArithmeticDecoder dec(stream);
    SymbolModel dm(n);
    std::size_t guessed = 0, guessed_last = 0;
    for (std::size_t i = 0; i < symbols.size(); ++i) {
        const SymbolModel::Guess guess = dm.guess();
        if (guess.low != guess.high || guess.last) ++guessed;
        if (guess.last) ++guessed_last;
        const std::uint32_t got = i % 3 == 2 ? dec.decode_symbol(dm) : dec.decode_likely_symbol(dm);
        ASSERT_EQ(got, symbols[i]) << "symbol " << i;
    }
    EXPECT_GT(guessed, 25000u);  // the guess was in play for most of the first four fifths
    EXPECT_GT(guessed_last, 10000u);
    EXPECT_EQ(dec.bytes_consumed(), stream.size());
}

// Both search paths (a count over a fixed width up to 16 symbols, a lookup table above) and the extremes.
INSTANTIATE_TEST_SUITE_P(Alphabets, ArithSymbolRoundTrip, ::testing::Values(2u, 3u, 16u, 17u, 33u, 256u, 2048u));

TEST(ArithDecoder, RoundTripsRawFieldsOfEveryWidth) {
    std::mt19937 rng(7);
    TestEncoder enc;
    std::vector<std::pair<std::uint32_t, std::uint32_t>> fields;  // (bits, value)
    for (int round = 0; round < 20; ++round) {
        for (std::uint32_t bits = 1; bits <= 32; ++bits) {
            const std::uint32_t v = bits == 32 ? rng() : rng() & ((1u << bits) - 1);
            fields.emplace_back(bits, v);
            enc.write_bits(bits, v);
        }
    }
    const std::uint64_t big = 0x0123456789ABCDEFull;
    enc.write_int64(big);
    enc.write_bits(8, 0xA5);
    enc.write_bits(16, 0xBEEF);
    const auto stream = enc.finish();

    ArithmeticDecoder dec(stream);
    for (const auto& [bits, v] : fields) ASSERT_EQ(dec.read_bits(bits), v) << bits << " bits";
    EXPECT_EQ(dec.read_int64(), big);
    EXPECT_EQ(dec.read_byte(), 0xA5);
    EXPECT_EQ(dec.read_short(), 0xBEEF);
}

TEST(ArithDecoder, ReadIntIsTwoShortsLowFirst) {
    TestEncoder enc;
    enc.write_bits(16, 0x5678);
    enc.write_bits(16, 0x1234);
    enc.write_bits(1, 1);
    const auto stream = enc.finish();
    ArithmeticDecoder dec(stream);
    EXPECT_EQ(dec.read_int(), 0x12345678u);
    EXPECT_EQ(dec.read_bit(), 1u);
}

// ---- bounds and corruption ----------------------------------------------------------------

TEST(ArithDecoder, NeverReadsPastTheEndOfItsSpan) {
    // A 5-byte window inside a larger buffer: the decoder must not see the bytes after it.
    std::vector<std::uint8_t> buffer(64, 0xAB);
    std::span<const std::uint8_t> window(buffer.data(), 5);
    ArithmeticDecoder dec(window);
    SymbolModel m(256);
    for (int i = 0; i < 1000; ++i) dec.decode_symbol(m);
    EXPECT_GT(dec.overrun(), 0u);
    // Past the end only zeros come in: the same as decoding a zero-padded copy.
    std::vector<std::uint8_t> padded(window.begin(), window.end());
    padded.resize(dec.bytes_consumed(), 0);
    ArithmeticDecoder a(window), b(padded);
    SymbolModel ma(256), mb(256);
    for (int i = 0; i < 1000; ++i) ASSERT_EQ(a.decode_symbol(ma), b.decode_symbol(mb));
    EXPECT_EQ(b.overrun(), 0u);
}

TEST(ArithDecoder, EmptyStreamDecodesZerosSafely) {
    ArithmeticDecoder dec(std::span<const std::uint8_t>{});
    BitModel bm;
    SymbolModel sm(40);
    for (int i = 0; i < 100; ++i) {
        EXPECT_EQ(dec.decode_bit(bm), 0u);
        EXPECT_EQ(dec.decode_symbol(sm), 0u);
    }
    EXPECT_EQ(dec.overrun(), dec.bytes_consumed());
}

TEST(ArithDecoder, ImpossibleRawValueIsAnError) {
    // A code value at the very top of the interval cannot come from an encoder.
    const std::vector<std::uint8_t> bytes = {0xFF, 0xFF, 0xFF, 0xFF};
    ArithmeticDecoder dec(bytes);
    EXPECT_THROW(dec.read_byte(), Error);
}

TEST(ArithDecoder, GarbageNeverEscapesTheModels) {
    // Random bytes through models of every kind of alphabet (the branch-free count of small ones,
    // the lookup table and scan up to the sentinel of large ones): every symbol stays in its
    // alphabet (and under the sanitizers, no search reads past its model).
    for (std::uint32_t symbols : {2u, 5u, 16u, 17u, 64u, 256u, 300u, kMaxSymbols}) {
        std::mt19937 rng(symbols);
        std::vector<std::uint8_t> bytes(4096);
        for (auto& b : bytes) b = static_cast<std::uint8_t>(rng());
        bytes[0] = bytes[1] = bytes[2] = bytes[3] = 0xFF;  // start beyond the interval
        ArithmeticDecoder dec(bytes);
        SymbolModel m(symbols);
        BitModel bm;
        for (int i = 0; i < 20000; ++i) {
            ASSERT_LT(dec.decode_symbol(m), symbols);
            ASSERT_LT(dec.decode_likely_symbol(m), symbols);
            ASSERT_LE(dec.decode_bit(bm), 1u);
        }
    }
}

}  // namespace
}  // namespace lidarscout::laz
