// Integer coding: corrector ranges for each parameter set, and round trips of values through
// the test encoder for the widths, contexts and ranges LAZ item coders use.
#include <gtest/gtest.h>

#include <limits>
#include <random>
#include <vector>

#include "core/error.hpp"
#include "laz/integer_decompressor.hpp"
#include "laz/integer_models.hpp"
#include "laz/test_arithmetic_encoder.hpp"

namespace lidarscout::laz {
namespace {

TEST(ArithIntegerModels, CorrectorRangeFollowsTheBits) {
    IntegerModels m16(16, 1, 8, 0);
    EXPECT_EQ(m16.corrector_bits(), 16u);
    EXPECT_EQ(m16.corrector_range(), 65536u);
    EXPECT_EQ(m16.corrector_min(), -32768);

    IntegerModels m32(32, 2, 8, 0);
    EXPECT_EQ(m32.corrector_bits(), 32u);
    EXPECT_EQ(m32.corrector_range(), 0u);  // 2^32
    EXPECT_EQ(m32.corrector_min(), std::numeric_limits<std::int32_t>::min());
    EXPECT_EQ(m32.contexts(), 2u);
    EXPECT_EQ(m32.class_model(1).symbols(), 33u);      // k = 0 .. 32
    EXPECT_EQ(m32.position_model(3).symbols(), 8u);    // 2^3
    EXPECT_EQ(m32.position_model(20).symbols(), 256u);  // capped at 2^bits_high
}

TEST(ArithIntegerModels, ExplicitRange) {
    IntegerModels odd(8, 1, 8, 100);  // not a power of two: 7 bits
    EXPECT_EQ(odd.corrector_bits(), 7u);
    EXPECT_EQ(odd.corrector_range(), 100u);
    EXPECT_EQ(odd.corrector_min(), -50);
    IntegerModels pow2(8, 1, 8, 64);  // a power of two: 6 bits
    EXPECT_EQ(pow2.corrector_bits(), 6u);
    EXPECT_EQ(pow2.corrector_min(), -32);
}

TEST(ArithIntegerModels, RejectsInvalidParameters) {
    EXPECT_THROW(IntegerModels(0, 1, 8, 0), Error);
    EXPECT_THROW(IntegerModels(33, 1, 8, 0), Error);
    EXPECT_THROW(IntegerModels(16, 0, 8, 0), Error);
    EXPECT_THROW(IntegerModels(16, 1, 0, 0), Error);
    EXPECT_THROW(IntegerModels(16, 1, 12, 0), Error);
}

struct IntegerCase {
    std::uint32_t bits, contexts, bits_high, range;
    const char* name;
};

class ArithIntegerRoundTrip : public ::testing::TestWithParam<IntegerCase> {};

// Values of the coded width, predictions near and far from them, across all contexts.
TEST_P(ArithIntegerRoundTrip, DecodesWhatWasEncoded) {
    const auto p = GetParam();
    std::mt19937 rng(p.bits * 31 + p.range);
    const std::uint64_t span = p.range ? p.range : (p.bits == 32 ? (1ull << 32) : (1ull << p.bits));
    auto draw = [&] { return static_cast<std::int32_t>(static_cast<std::uint32_t>(rng() % span)); };
    struct Item { std::int32_t pred, real; std::uint32_t ctx; };
    std::vector<Item> items;
    std::int32_t previous = 0;
    for (int i = 0; i < 5000; ++i) {
        std::int32_t real;
        if (i % 3 == 0) {
            real = draw();  // anything
        } else {            // close to the prediction, as real data mostly is
            const std::uint32_t near = static_cast<std::uint32_t>(previous) + (rng() % 9) - 4;
            real = static_cast<std::int32_t>(p.range || p.bits < 32 ? near % span : near);
        }
        items.push_back({previous, real, static_cast<std::uint32_t>(i) % p.contexts});
        previous = real;
    }
    if (p.bits == 32) items.push_back({0, std::numeric_limits<std::int32_t>::min(), 0});  // k == 32

    test::TestEncoder enc;
    IntegerModels em(p.bits, p.contexts, p.bits_high, p.range);
    for (const auto& it : items) test::encode_integer(enc, em, it.pred, it.real, it.ctx);
    const auto stream = enc.finish();

    ArithmeticDecoder dec(stream);
    IntegerDecompressor ic(p.bits, p.contexts, p.bits_high, p.range);
    for (std::size_t i = 0; i < items.size(); ++i) {
        ASSERT_EQ(ic.decompress(dec, items[i].pred, items[i].ctx), items[i].real) << "value " << i;
    }
    EXPECT_EQ(dec.overrun(), 0u);
}

INSTANTIATE_TEST_SUITE_P(
    Widths, ArithIntegerRoundTrip,
    ::testing::Values(IntegerCase{32, 2, 8, 0, "bits32"}, IntegerCase{16, 1, 8, 0, "bits16"},
                      IntegerCase{8, 4, 8, 0, "bits8_4contexts"}, IntegerCase{1, 1, 8, 0, "bits1"},
                      IntegerCase{32, 1, 11, 0, "bits32_high11"}, IntegerCase{32, 3, 4, 0, "bits32_high4"},
                      IntegerCase{8, 1, 8, 100, "range100"}, IntegerCase{8, 1, 8, 256, "range256"}),
    [](const auto& info) { return std::string(info.param.name); });

TEST(ArithIntegerDecompressor, LastClassIsTheCorrectorsSize) {
    test::TestEncoder enc;
    IntegerModels em(16, 1, 8, 0);
    test::encode_integer(enc, em, 100, 100, 0);  // corrector 0: class 0
    test::encode_integer(enc, em, 100, 101, 0);  // 1: class 0
    test::encode_integer(enc, em, 100, 102, 0);  // 2: class 1
    test::encode_integer(enc, em, 100, 96, 0);   // -4: class 3 ([-7, -4])
    test::encode_integer(enc, em, 0, 1000, 0);   // 1000: class 10 ([513, 1024])
    const auto stream = enc.finish();
    ArithmeticDecoder dec(stream);
    IntegerDecompressor ic(16, 1, 8, 0);
    const std::uint32_t classes[] = {0, 0, 1, 3, 10};
    const std::int32_t preds[] = {100, 100, 100, 100, 0};
    const std::int32_t reals[] = {100, 101, 102, 96, 1000};
    for (int i = 0; i < 5; ++i) {
        EXPECT_EQ(ic.decompress(dec, preds[i], 0), reals[i]);
        EXPECT_EQ(ic.last_class(), classes[i]);
    }
}

TEST(ArithIntegerDecompressor, ResetForgetsWhatWasLearned) {
    // Encode the same values twice from fresh models; decode with one decompressor reset in
    // between: it must match, and without the reset it must not.
    test::TestEncoder enc;
    for (int pass = 0; pass < 2; ++pass) {
        IntegerModels em(16, 1, 8, 0);
        for (int i = 0; i < 200; ++i) test::encode_integer(enc, em, 0, 3, 0);
    }
    const auto stream = enc.finish();
    auto decode = [&](bool reset) {
        ArithmeticDecoder dec(stream);
        IntegerDecompressor ic(16, 1, 8, 0);
        int wrong = 0;
        for (int pass = 0; pass < 2; ++pass) {
            if (pass == 1 && reset) ic.reset();
            for (int i = 0; i < 200; ++i) wrong += ic.decompress(dec, 0, 0) != 3;
        }
        return wrong;
    };
    EXPECT_EQ(decode(true), 0);
    EXPECT_GT(decode(false), 0);
}

}  // namespace
}  // namespace lidarscout::laz
