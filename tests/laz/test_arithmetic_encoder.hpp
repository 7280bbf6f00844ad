// A minimal arithmetic encoder for tests only: the mirror image of laz::ArithmeticDecoder
// (and of the integer coding), so that tests can produce streams with known content and
// check that decoding gives it back. The product encoder will live in src/laz/ later; this
// one favours plainness (a growing byte vector, carries propagated by walking back).
#pragma once

#include <cstdint>
#include <vector>

#include "laz/arithmetic_models.hpp"
#include "laz/integer_models.hpp"

namespace lidarscout::laz::test {

class TestEncoder {
public:
    void encode_bit(BitModel& m, std::uint32_t bit) {
        const std::uint32_t split = m.zero_probability() * (length_ >> kBitProbabilityBits);
        if (bit == 0) {
            length_ = split;
        } else {
            add(split);
            length_ -= split;
        }
        if (length_ < kMinLength) renormalize();
        m.record(bit);
    }

    void encode_symbol(SymbolModel& m, std::uint32_t s) {
        std::uint32_t low;
        if (s == m.last_symbol()) {
            low = m.cdf(s) * (length_ >> kSymbolProbabilityBits);
            length_ -= low;
        } else {
            length_ >>= kSymbolProbabilityBits;
            low = m.cdf(s) * length_;
            length_ = m.cdf(s + 1) * length_ - low;
        }
        add(low);
        if (length_ < kMinLength) renormalize();
        m.record(s);
    }

    // 1 to 32 raw bits (more than 19 go out as the low 16, then the rest).
    void write_bits(std::uint32_t bits, std::uint32_t v) {
        if (bits > 19) {
            write_raw(16, v & 0xFFFFu);
            v >>= 16;
            bits -= 16;
        }
        write_raw(bits, v);
    }
    void write_int64(std::uint64_t v) {
        for (int i = 0; i < 4; ++i) write_raw(16, static_cast<std::uint32_t>(v >> (16 * i)) & 0xFFFFu);
    }

    // Closes the stream the way LASzip writers do (including the trailing zero bytes).
    std::vector<std::uint8_t> finish() {
        const std::uint32_t before = base_;
        bool third_zero = true;
        if (length_ > 2 * kMinLength) {
            base_ += kMinLength;
            length_ = kMinLength >> 1;
        } else {
            base_ += kMinLength >> 1;
            length_ = kMinLength >> 9;
            third_zero = false;
        }
        if (base_ < before) carry();
        renormalize();
        out_.push_back(0);
        out_.push_back(0);
        if (third_zero) out_.push_back(0);
        return out_;
    }

private:
    static constexpr std::uint32_t kMinLength = 0x01000000u;

    void write_raw(std::uint32_t bits, std::uint32_t v) {
        length_ >>= bits;
        add(v * length_);
        if (length_ < kMinLength) renormalize();
    }
    void add(std::uint32_t x) {
        const std::uint32_t before = base_;
        base_ += x;
        if (base_ < before) carry();
    }
    void carry() {
        for (std::size_t i = out_.size(); i-- > 0;) {
            if (out_[i] != 0xFF) {
                ++out_[i];
                return;
            }
            out_[i] = 0;
        }
    }
    void renormalize() {
        do {
            out_.push_back(static_cast<std::uint8_t>(base_ >> 24));
            base_ <<= 8;
        } while ((length_ <<= 8) < kMinLength);
    }

    std::vector<std::uint8_t> out_;
    std::uint32_t base_ = 0;
    std::uint32_t length_ = 0xFFFFFFFFu;
};

// Integer coding, encoder side: `real` after `prediction`, with the same models a decoder uses.
inline void encode_integer(TestEncoder& enc, IntegerModels& m, std::int32_t prediction, std::int32_t real,
                           std::uint32_t context) {
    const std::uint32_t range = m.corrector_range();
    std::uint32_t c = static_cast<std::uint32_t>(real) - static_cast<std::uint32_t>(prediction);
    if (range != 0) {  // fold into [corrector_min, corrector_min + range - 1]
        const std::int64_t lo = m.corrector_min();
        const std::int64_t hi = lo + range - 1;
        const std::int64_t sc = static_cast<std::int32_t>(c);
        if (sc < lo) c += range;
        else if (sc > hi) c -= range;
    }
    const std::int32_t sc = static_cast<std::int32_t>(c);
    std::uint32_t magnitude = sc <= 0 ? 0u - c : c - 1;
    std::uint32_t k = 0;
    for (; magnitude; magnitude >>= 1) ++k;
    enc.encode_symbol(m.class_model(context), k);
    if (k == 0) {
        enc.encode_bit(m.unit_model(), c);
        return;
    }
    if (k >= 32) return;  // the corrector is corrector_min
    const std::uint32_t position = sc < 0 ? c + ((1u << k) - 1) : c - 1;
    if (k <= m.bits_high()) {
        enc.encode_symbol(m.position_model(k), position);
    } else {
        const std::uint32_t low_bits = k - m.bits_high();
        enc.encode_symbol(m.position_model(k), position >> low_bits);
        enc.write_bits(low_bits, position & ((1u << low_bits) - 1));
    }
}

}  // namespace lidarscout::laz::test
