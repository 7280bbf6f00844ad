// Bit-exactness against LASzip over long streams. Each workload below (a fixed pseudo-random
// sequence of bits, symbols, raw fields or integers) was encoded once with the LASzip 3.4
// library's own ArithmeticEncoder / IntegerCompressor, and the size and FNV-1a hash of its
// output recorded here. Our test encoder, driven by our models, must produce the very same
// bytes (so the models adapt exactly like LASzip's, including count halving and the update
// schedule, which short streams never reach), and our decoder must read the sequence back.
#include <gtest/gtest.h>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "laz/arithmetic_decoder.hpp"
#include "laz/arithmetic_models.hpp"
#include "laz/integer_decompressor.hpp"
#include "laz/integer_models.hpp"
#include "laz/test_arithmetic_encoder.hpp"

namespace lidarscout::laz {
namespace {

// 64-bit LCG (Knuth's MMIX constants), top 31 bits.
class Sequence {
public:
    explicit Sequence(std::uint64_t seed) : state_(seed) {}
    std::uint32_t next() {
        state_ = state_ * 6364136223846793005ull + 1442695040888963407ull;
        return static_cast<std::uint32_t>(state_ >> 33);
    }
    std::uint32_t next32() { return next() ^ (next() << 16); }

private:
    std::uint64_t state_;
};

std::uint64_t fnv1a(const std::vector<std::uint8_t>& bytes) {
    std::uint64_t h = 1469598103934665603ull;
    for (auto b : bytes) {
        h ^= b;
        h *= 1099511628211ull;
    }
    return h;
}

// What LASzip wrote for a workload.
struct Reference {
    std::size_t size;
    std::uint64_t hash;
};

void expect_same_stream(const std::vector<std::uint8_t>& ours, Reference laszip) {
    EXPECT_EQ(ours.size(), laszip.size);
    EXPECT_EQ(fnv1a(ours), laszip.hash) << "stream differs from LASzip's";
}

// ---- bits: one model, three regimes of P(1) (5%, 60%, 95%) --------------------------------------

std::vector<std::uint32_t> bit_workload() {
    Sequence r(1);
    std::vector<std::uint32_t> bits(60000);
    for (int i = 0; i < 60000; ++i) {
        const std::uint32_t per_mille = i < 20000 ? 50 : i < 40000 ? 600 : 950;
        bits[i] = (r.next() % 1000) < per_mille;
    }
    return bits;
}

TEST(ArithGolden, BitsMatchLaszip) {
    const auto bits = bit_workload();
    test::TestEncoder enc;
    BitModel em;
    for (auto b : bits) enc.encode_bit(em, b);
    const auto stream = enc.finish();
    expect_same_stream(stream, {4542, 0x0af5e6da43af6b84ull});

    ArithmeticDecoder dec(stream);
    BitModel dm;
    for (std::size_t i = 0; i < bits.size(); ++i) ASSERT_EQ(dec.decode_bit(dm), bits[i]) << i;
    EXPECT_EQ(dec.overrun(), 0u);
}

// Long runs: 30,000 zeros (the counts saturate and are halved with p0 kept below 1), 30,000
// ones (the model has to swing over), then 20,000 fair coin flips.
TEST(ArithGolden, BitRunsMatchLaszip) {
    Sequence r(2);
    std::vector<std::uint32_t> bits(80000);
    for (int i = 0; i < 80000; ++i) bits[i] = i < 30000 ? 0 : i < 60000 ? 1 : (r.next() & 1);
    test::TestEncoder enc;
    BitModel em;
    for (auto b : bits) enc.encode_bit(em, b);
    const auto stream = enc.finish();
    expect_same_stream(stream, {4769, 0x79d5a3f11408f4f1ull});

    ArithmeticDecoder dec(stream);
    BitModel dm;
    for (std::size_t i = 0; i < bits.size(); ++i) ASSERT_EQ(dec.decode_bit(dm), bits[i]) << i;
}

// ---- symbols: skewed towards 0, with the last symbol every 97th ----------------------------------

std::vector<std::uint32_t> symbol_workload(std::uint32_t n) {
    Sequence r(n);
    std::vector<std::uint32_t> symbols(40000);
    for (int i = 0; i < 40000; ++i) {
        const std::uint64_t a = r.next() % n, b = r.next() % n;
        symbols[i] = i % 97 == 0 ? n - 1 : static_cast<std::uint32_t>(a * b / n);
    }
    return symbols;
}

struct SymbolCase {
    std::uint32_t symbols;
    Reference laszip;
};

class ArithGoldenSymbols : public ::testing::TestWithParam<SymbolCase> {};

TEST_P(ArithGoldenSymbols, MatchLaszip) {
    const auto [n, laszip] = GetParam();
    const auto symbols = symbol_workload(n);
    test::TestEncoder enc;
    SymbolModel em(n);
    for (auto s : symbols) enc.encode_symbol(em, s);
    const auto stream = enc.finish();
    expect_same_stream(stream, laszip);

    ArithmeticDecoder dec(stream);
    SymbolModel dm(n);
    for (std::size_t i = 0; i < symbols.size(); ++i) ASSERT_EQ(dec.decode_symbol(dm), symbols[i]) << i;
    EXPECT_EQ(dec.overrun(), 0u);
}

INSTANTIATE_TEST_SUITE_P(Alphabets, ArithGoldenSymbols,
                         ::testing::Values(SymbolCase{2, {418, 0xa8adcf5ffdf0504aull}},
                                           SymbolCase{5, {6935, 0x31822e2c13f3cdbdull}},
                                           SymbolCase{16, {16437, 0xa6b1d9a80bb9a3e3ull}},
                                           SymbolCase{17, {16835, 0xb2cf15e390680d4dull}},
                                           SymbolCase{64, {26883, 0x4d0c01d456d6245cull}},
                                           SymbolCase{256, {37045, 0x2187a24d6584f4bfull}},
                                           SymbolCase{2048, {52456, 0x62c923f0aad48859ull}}),
                         [](const auto& info) { return std::to_string(info.param.symbols) + "_symbols"; });

// ---- raw fields of 1..32 bits --------------------------------------------------------------------

TEST(ArithGolden, RawFieldsMatchLaszip) {
    Sequence r(99);
    std::vector<std::pair<std::uint32_t, std::uint32_t>> fields;
    for (int i = 0; i < 4000; ++i) {
        const std::uint32_t bits = 1 + i % 32;
        std::uint32_t v = r.next32();
        if (bits < 32) v &= (1u << bits) - 1;
        fields.emplace_back(bits, v);
    }
    test::TestEncoder enc;
    for (auto [bits, v] : fields) enc.write_bits(bits, v);
    const auto stream = enc.finish();
    expect_same_stream(stream, {8254, 0x83e7ef8ba08077e1ull});

    ArithmeticDecoder dec(stream);
    for (std::size_t i = 0; i < fields.size(); ++i) ASSERT_EQ(dec.read_bits(fields[i].first), fields[i].second) << i;
}

// ---- integers: (prediction = previous value, value, context) -------------------------------------

struct Coded {
    std::int32_t prediction, value;
    std::uint32_t context;
};

struct IntegerWorkload {
    const char* name;
    std::uint32_t bits, contexts;
    Reference laszip;
    std::function<std::vector<Coded>()> make;
};

std::vector<IntegerWorkload> integer_workloads() {
    return {
        {"bits32_2contexts", 32, 2, {43478, 0xbaedc48fb6805384ull},
         [] {  // a random walk of +-1000 with a wild jump every 50th value
             Sequence r(32);
             std::vector<Coded> out;
             std::int32_t prev = 0;
             for (int i = 0; i < 30000; ++i) {
                 const std::int32_t v = i % 50 == 0 ? static_cast<std::int32_t>(r.next32())
                                                    : static_cast<std::int32_t>(static_cast<std::uint32_t>(prev) +
                                                                                (r.next() % 2001) - 1000);
                 out.push_back({prev, v, static_cast<std::uint32_t>(i % 2)});
                 prev = v;
             }
             return out;
         }},
        {"bits16", 16, 1, {30255, 0x7e730201addd228aull},
         [] {  // a wrapping 16-bit walk of +-100, re-drawn every 40th value
             Sequence r(16);
             std::vector<Coded> out;
             std::int32_t prev = 0;
             for (int i = 0; i < 30000; ++i) {
                 std::int32_t v =
                     static_cast<std::int32_t>((static_cast<std::uint32_t>(prev) + (r.next() % 201) - 100) & 0xFFFF);
                 if (i % 40 == 0) v = static_cast<std::int32_t>(r.next() & 0xFFFF);
                 out.push_back({prev, v, 0});
                 prev = v;
             }
             return out;
         }},
        {"bits8_3contexts", 8, 3, {16037, 0x4b8904a18a2cd3aeull},
         [] {  // bytes: every third random, the others within +-2 of the previous
             Sequence r(8);
             std::vector<Coded> out;
             std::int32_t prev = 0;
             for (int i = 0; i < 30000; ++i) {
                 std::int32_t v = static_cast<std::int32_t>(r.next() & 0xFF);
                 if (i % 3) v = (prev + static_cast<std::int32_t>(r.next() % 5) - 2) & 0xFF;
                 out.push_back({prev, v, static_cast<std::uint32_t>(i % 3)});
                 prev = v;
             }
             return out;
         }},
    };
}

class ArithGoldenIntegers : public ::testing::TestWithParam<IntegerWorkload> {};

TEST_P(ArithGoldenIntegers, MatchLaszip) {
    const auto& w = GetParam();
    const auto values = w.make();
    test::TestEncoder enc;
    IntegerModels em(w.bits, w.contexts, 8, 0);
    for (const auto& c : values) test::encode_integer(enc, em, c.prediction, c.value, c.context);
    const auto stream = enc.finish();
    expect_same_stream(stream, w.laszip);

    ArithmeticDecoder dec(stream);
    IntegerDecompressor ic(w.bits, w.contexts);
    for (std::size_t i = 0; i < values.size(); ++i) {
        ASSERT_EQ(ic.decompress(dec, values[i].prediction, values[i].context), values[i].value) << i;
    }
    EXPECT_EQ(dec.overrun(), 0u);
}

INSTANTIATE_TEST_SUITE_P(Widths, ArithGoldenIntegers, ::testing::ValuesIn(integer_workloads()),
                         [](const auto& info) { return std::string(info.param.name); });

}  // namespace
}  // namespace lidarscout::laz
