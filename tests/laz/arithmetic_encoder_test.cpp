// The arithmetic encoder and the integer compressor: long random mixes of every coding
// operation decode back exactly (and leave no read past the end), carries (also chains of
// them through 0xFF bytes) reach the bytes already written, both ways of closing a stream
// give LASzip's padding, a stream appended to other bytes leaves them alone, and the output
// is byte-identical to the plain test encoder of tests/laz/test_arithmetic_encoder.hpp.
#include <gtest/gtest.h>

#include <cstdint>
#include <limits>
#include <random>
#include <variant>
#include <vector>

#include "laz/arithmetic_decoder.hpp"
#include "laz/arithmetic_encoder.hpp"
#include "laz/integer_compressor.hpp"
#include "laz/integer_decompressor.hpp"
#include "laz/test_arithmetic_encoder.hpp"

namespace lidarscout::laz {
namespace {

// ---- one random script of coding operations, run through any encoder and the decoder ----

struct BitOp { int model; std::uint32_t bit; };
struct SymbolOp { int model; std::uint32_t symbol; };
struct RawOp { std::uint32_t bits; std::uint32_t value; };  // 1..32 bits
struct Int64Op { std::uint64_t value; };
using Op = std::variant<BitOp, SymbolOp, RawOp, Int64Op>;

// Alphabet sizes of the symbol models: small ones, the >16 ones with a decoder lookup
// table, and the largest allowed.
const std::vector<std::uint32_t> kAlphabets = {2, 3, 16, 17, 64, 256, 517, 2048};

struct Models {
    std::vector<BitModel> bits = std::vector<BitModel>(3);
    std::vector<SymbolModel> symbols;
    Models() {
        for (std::uint32_t n : kAlphabets) symbols.emplace_back(n);
    }
};

// Skewed choices, so that models adapt to very unequal probabilities (long intervals of
// one symbol, small ones of others: that is when carries and multi-byte renormalisations
// happen).
std::vector<Op> random_script(std::uint32_t seed, std::size_t count) {
    std::mt19937 rng(seed);
    std::vector<Op> ops;
    ops.reserve(count);
    for (std::size_t i = 0; i < count; ++i) {
        const std::uint32_t kind = rng() % 10;
        if (kind < 4) {
            const int model = static_cast<int>(rng() % 3);
            const std::uint32_t bit = model == 0 ? (rng() % 50 == 0) : model == 1 ? (rng() % 50 != 0) : rng() & 1;
            ops.push_back(BitOp{model, bit});
        } else if (kind < 8) {
            const int model = static_cast<int>(rng() % kAlphabets.size());
            const std::uint32_t n = kAlphabets[static_cast<std::size_t>(model)];
            const std::uint32_t symbol = rng() % 4 == 0 ? rng() % n : (rng() % 3 == 0 ? n - 1 : 0);
            ops.push_back(SymbolOp{model, symbol});
        } else if (kind < 9) {
            const std::uint32_t bits = 1 + rng() % 32;
            const auto value = static_cast<std::uint32_t>(rng());
            ops.push_back(RawOp{bits, bits == 32 ? value : value & ((1u << bits) - 1)});
        } else {
            ops.push_back(Int64Op{(std::uint64_t{rng()} << 32) | rng()});
        }
    }
    return ops;
}

std::vector<std::uint8_t> encode_script(const std::vector<Op>& ops) {
    Models m;
    std::vector<std::uint8_t> out;
    ArithmeticEncoder enc;
    enc.start(out);
    for (const Op& op : ops) {
        if (const auto* b = std::get_if<BitOp>(&op)) enc.encode_bit(m.bits[b->model], b->bit);
        else if (const auto* s = std::get_if<SymbolOp>(&op)) enc.encode_symbol(m.symbols[s->model], s->symbol);
        else if (const auto* r = std::get_if<RawOp>(&op)) enc.write_bits(r->bits, r->value);
        else enc.write_int64(std::get<Int64Op>(op).value);
    }
    enc.done();
    return out;
}

std::vector<std::uint8_t> encode_script_with_test_encoder(const std::vector<Op>& ops) {
    Models m;
    test::TestEncoder enc;
    for (const Op& op : ops) {
        if (const auto* b = std::get_if<BitOp>(&op)) enc.encode_bit(m.bits[b->model], b->bit);
        else if (const auto* s = std::get_if<SymbolOp>(&op)) enc.encode_symbol(m.symbols[s->model], s->symbol);
        else if (const auto* r = std::get_if<RawOp>(&op)) enc.write_bits(r->bits, r->value);
        else enc.write_int64(std::get<Int64Op>(op).value);
    }
    return enc.finish();
}

// Decodes `ops` from `stream` and checks every value; returns the number of mismatches.
std::size_t check_decodes(const std::vector<Op>& ops, std::span<const std::uint8_t> stream) {
    Models m;
    ArithmeticDecoder dec(stream);
    std::size_t wrong = 0;
    for (const Op& op : ops) {
        if (const auto* b = std::get_if<BitOp>(&op)) wrong += dec.decode_bit(m.bits[b->model]) != b->bit;
        else if (const auto* s = std::get_if<SymbolOp>(&op))
            wrong += dec.decode_symbol(m.symbols[s->model]) != s->symbol;
        else if (const auto* r = std::get_if<RawOp>(&op)) wrong += dec.read_bits(r->bits) != r->value;
        else wrong += dec.read_int64() != std::get<Int64Op>(op).value;
    }
    EXPECT_EQ(dec.overrun(), 0u) << "the decoder read past the padding";
    return wrong;
}

TEST(ArithmeticEncoder, RandomScriptsDecodeExactly) {
    for (std::uint32_t seed = 1; seed <= 6; ++seed) {
        const auto ops = random_script(seed, 200000);
        const auto stream = encode_script(ops);
        EXPECT_EQ(check_decodes(ops, stream), 0u) << "seed " << seed;
    }
}

TEST(ArithmeticEncoder, MatchesTheTestEncoderByteForByte) {
    for (std::uint32_t seed = 11; seed <= 16; ++seed) {
        const auto ops = random_script(seed, 100000);
        EXPECT_EQ(encode_script(ops), encode_script_with_test_encoder(ops)) << "seed " << seed;
    }
}

TEST(ArithmeticEncoder, ShortScriptsOfEveryLengthDecode) {
    // Short streams end in every possible state; both ways of closing must decode.
    for (std::size_t n = 0; n < 64; ++n) {
        const auto ops = random_script(static_cast<std::uint32_t>(100 + n), n);
        const auto stream = encode_script(ops);
        EXPECT_EQ(check_decodes(ops, stream), 0u) << n << " operations";
        EXPECT_EQ(stream, encode_script_with_test_encoder(ops)) << n << " operations";
    }
}

// ---- carries and the end of a stream ----

TEST(ArithmeticEncoder, CarryRunsBackThroughFfBytes) {
    // Raw bytes chosen so that the last one overflows the base while the three bytes before
    // it are 0xFF: they must become 0x00 and the byte before them grow by one.
    const std::vector<std::uint8_t> values = {128, 254, 98, 255, 254, 127, 127, 127, 127, 127, 127, 255};
    std::vector<std::uint8_t> out;
    ArithmeticEncoder enc;
    enc.start(out);
    for (std::uint8_t v : values) enc.write_byte(v);
    enc.done();
    const std::vector<std::uint8_t> settled = {128, 254, 98, 127, 0, 28, 127, 129, 0, 0, 0, 127};
    ASSERT_GE(out.size(), settled.size());
    EXPECT_EQ(std::vector<std::uint8_t>(out.begin(), out.begin() + 12), settled);
    ArithmeticDecoder dec(out);
    for (std::uint8_t v : values) EXPECT_EQ(dec.read_byte(), v);
}

TEST(ArithmeticEncoder, EmptyStreamIsOneByteAndThreeZeros) {
    std::vector<std::uint8_t> out;
    ArithmeticEncoder enc;
    enc.start(out);
    enc.done();
    EXPECT_EQ(out, (std::vector<std::uint8_t>{0x01, 0, 0, 0}));
}

TEST(ArithmeticEncoder, NarrowFinalIntervalEndsWithTwoBytesAndTwoZeros) {
    // These writes leave an interval of 2^25 - 2: too narrow for a one-byte end.
    std::vector<std::uint8_t> out;
    ArithmeticEncoder enc;
    enc.start(out);
    enc.write_byte(0xFF);
    enc.write_bits(7, 0);  // length 2^25 - 2^17: below twice the minimum
    enc.done();
    ASSERT_EQ(out.size(), 5u);
    EXPECT_EQ(out[3], 0);
    EXPECT_EQ(out[4], 0);
    ArithmeticDecoder dec(out);
    EXPECT_EQ(dec.read_byte(), 0xFF);
    EXPECT_EQ(dec.read_bits(7), 0u);
    EXPECT_EQ(dec.overrun(), 0u);
}

TEST(ArithmeticEncoder, AppendsAfterExistingBytesWithoutTouchingThem) {
    const auto ops = random_script(77, 50000);
    const auto alone = encode_script(ops);
    std::vector<std::uint8_t> out(1000, 0xFF);  // 0xFF: a stray carry would show here
    Models m;
    ArithmeticEncoder enc;
    enc.start(out);
    for (const Op& op : ops) {
        if (const auto* b = std::get_if<BitOp>(&op)) enc.encode_bit(m.bits[b->model], b->bit);
        else if (const auto* s = std::get_if<SymbolOp>(&op)) enc.encode_symbol(m.symbols[s->model], s->symbol);
        else if (const auto* r = std::get_if<RawOp>(&op)) enc.write_bits(r->bits, r->value);
        else enc.write_int64(std::get<Int64Op>(op).value);
    }
    enc.done();
    ASSERT_EQ(out.size(), 1000 + alone.size());
    EXPECT_EQ(std::vector<std::uint8_t>(out.begin(), out.begin() + 1000), std::vector<std::uint8_t>(1000, 0xFF));
    EXPECT_EQ(std::vector<std::uint8_t>(out.begin() + 1000, out.end()), alone);
}

TEST(ArithmeticEncoder, RestartsCleanlyForTheNextStream) {
    const auto a = random_script(5, 3000);
    const auto b = random_script(6, 3000);
    std::vector<std::uint8_t> out;
    ArithmeticEncoder enc;
    for (const auto* ops : {&a, &b}) {
        Models m;
        enc.start(out);
        for (const Op& op : *ops) {
            if (const auto* s = std::get_if<SymbolOp>(&op)) enc.encode_symbol(m.symbols[s->model], s->symbol);
        }
        enc.done();
    }
    // Only the symbols were coded; compare with each script's symbols coded alone.
    const auto symbols_only = [](const std::vector<Op>& ops) {
        std::vector<Op> s;
        for (const Op& op : ops) {
            if (std::holds_alternative<SymbolOp>(op)) s.push_back(op);
        }
        return encode_script(s);
    };
    auto expected = symbols_only(a);
    const auto second = symbols_only(b);
    expected.insert(expected.end(), second.begin(), second.end());
    EXPECT_EQ(out, expected);
}

// ---- the integer compressor ----

struct IntCase {
    std::uint32_t bits, contexts, bits_high, range;
};

// Values and predictions around every edge: zero, class boundaries, the extremes of the
// coded range and of int32 (where correctors wrap).
std::vector<std::int32_t> edge_values(const IntCase& c) {
    std::vector<std::int32_t> v = {0, 1, -1, 2, -2, 3, 255, 256, -256, 32767, -32768, 65535};
    for (int k = 1; k < 32; ++k) {
        v.push_back(static_cast<std::int32_t>(1u << k));
        v.push_back(static_cast<std::int32_t>((1u << k) - 1));
        v.push_back(-static_cast<std::int32_t>(1u << (k - 1)));
    }
    v.push_back(std::numeric_limits<std::int32_t>::max());
    v.push_back(std::numeric_limits<std::int32_t>::min());
    if (c.range != 0) v.push_back(static_cast<std::int32_t>(c.range - 1));
    return v;
}

// Values are coded modulo the range: they come back reduced into it.
std::int32_t in_range(std::int32_t v, const IntCase& c) {
    std::uint64_t range = c.range ? c.range : (c.bits < 32 ? (1ull << c.bits) : 0);
    if (range == 0) return v;
    return static_cast<std::int32_t>(static_cast<std::uint64_t>(static_cast<std::uint32_t>(v)) % range);
}

TEST(IntegerEncoder, EveryCorrectorRoundTrips) {
    const std::vector<IntCase> cases = {{32, 1, 8, 0},  {32, 22, 8, 0}, {16, 4, 8, 0},
                                        {8, 1, 8, 0},   {1, 1, 1, 0},   {32, 2, 11, 0},
                                        {24, 3, 6, 0},  {16, 1, 8, 1000}, {32, 1, 8, 3}};
    for (const IntCase& c : cases) {
        SCOPED_TRACE("bits " + std::to_string(c.bits) + " range " + std::to_string(c.range));
        const auto values = edge_values(c);
        std::mt19937 rng(c.bits * 31 + c.range);
        struct Coded { std::int32_t prediction, value; std::uint32_t context; };
        std::vector<Coded> coded;
        for (std::int32_t p : values) {
            for (std::int32_t v : values) {
                const std::int32_t pred = in_range(p, c), val = in_range(v, c);
                coded.push_back({pred, val, static_cast<std::uint32_t>(rng() % c.contexts)});
            }
        }
        std::vector<std::uint8_t> stream;
        ArithmeticEncoder enc;
        IntegerCompressor ic(c.bits, c.contexts, c.bits_high, c.range);
        enc.start(stream);
        std::vector<std::uint32_t> classes;
        for (const Coded& x : coded) {
            ic.compress(enc, x.prediction, x.value, x.context);
            classes.push_back(ic.last_class());
        }
        enc.done();

        ArithmeticDecoder dec(stream);
        IntegerDecompressor id(c.bits, c.contexts, c.bits_high, c.range);
        std::size_t wrong = 0, wrong_class = 0;
        for (std::size_t i = 0; i < coded.size(); ++i) {
            wrong += id.decompress(dec, coded[i].prediction, coded[i].context) != coded[i].value;
            wrong_class += id.last_class() != classes[i];
        }
        EXPECT_EQ(wrong, 0u);
        EXPECT_EQ(wrong_class, 0u);
        EXPECT_EQ(dec.overrun(), 0u);
    }
}

TEST(IntegerEncoder, MatchesTheTestEncodersIntegerCoding) {
    std::mt19937 rng(9);
    std::vector<std::uint8_t> ours;
    ArithmeticEncoder enc;
    IntegerCompressor ic(32, 3);
    IntegerModels models(32, 3, 8, 0);
    test::TestEncoder reference;
    enc.start(ours);
    for (int i = 0; i < 100000; ++i) {
        const auto prediction = static_cast<std::int32_t>(rng());
        const auto value = static_cast<std::int32_t>(static_cast<std::uint32_t>(prediction) +
                                                     rng() % (1u << (rng() % 32)) - rng() % 1000);
        const std::uint32_t context = rng() % 3;
        ic.compress(enc, prediction, value, context);
        test::encode_integer(reference, models, prediction, value, context);
    }
    enc.done();
    EXPECT_EQ(ours, reference.finish());
}

}  // namespace
}  // namespace lidarscout::laz
