// Encoding side of LASzip's integer coding, the inverse of IntegerDecompressor: the corrector
// c = value - prediction is folded into the coded range, then written as its size class k
// and its position within that class, under the shared IntegerModels. Item encoders keep
// one of these per field and reset it at every chunk.
#pragma once

#include <bit>
#include <cstdint>

#include "laz/arithmetic_encoder.hpp"
#include "laz/integer_models.hpp"

namespace lidarscout::laz {

class IntegerCompressor {
public:
    // See IntegerModels for the parameters; the defaults are LASzip's.
    explicit IntegerCompressor(std::uint32_t bits = 16, std::uint32_t contexts = 1, std::uint32_t bits_high = 8,
                               std::uint32_t range = 0)
        : models_(bits, contexts, bits_high, range) {}

    // Back to the start state (at the start of every chunk).
    void reset() { models_.reset(); }

    // Codes `value` after `prediction` in `context` (< contexts()).
    void compress(ArithmeticEncoder& enc, std::int32_t prediction, std::int32_t value, std::uint32_t context = 0) {
        write_corrector(enc, fold(static_cast<std::uint32_t>(value) - static_cast<std::uint32_t>(prediction)),
                        context);
    }

    // Size class k of the last coded corrector (item encoders use it as a context, exactly
    // as the decoders use IntegerDecompressor::last_class()).
    std::uint32_t last_class() const { return k_; }
    std::uint32_t contexts() const { return models_.contexts(); }

private:
    // The difference (mod 2^32) moved into [corrector_min, corrector_min + range - 1].
    std::int32_t fold(std::uint32_t difference) const {
        const std::uint32_t range = models_.corrector_range();
        const auto c = static_cast<std::int32_t>(difference);
        if (range == 0) return c;  // 32-bit values: every difference is already in range
        const std::int64_t min = models_.corrector_min();
        if (c < min) return static_cast<std::int32_t>(difference + range);
        if (c > min + range - 1) return static_cast<std::int32_t>(difference - range);
        return c;
    }

    void write_corrector(ArithmeticEncoder& enc, std::int32_t c, std::uint32_t context) {
        const auto u = static_cast<std::uint32_t>(c);
        // Class k holds [-(2^k - 1), 2^k]; class 0 holds 0 and 1.
        k_ = static_cast<std::uint32_t>(std::bit_width(c <= 0 ? 0u - u : u - 1));
        enc.encode_symbol(models_.class_model(context), k_);
        if (k_ == 0) {
            enc.encode_bit(models_.unit_model(), u);
            return;
        }
        if (k_ >= 32) return;  // only corrector_min lies there: the class says it all
        // Negative correctors take positions 0 .. 2^(k-1)-1, positive ones 2^(k-1) .. 2^k-1.
        const std::uint32_t position = c < 0 ? u + ((1u << k_) - 1) : u - 1;
        const std::uint32_t bits_high = models_.bits_high();
        if (k_ <= bits_high) {
            enc.encode_symbol(models_.position_model(k_), position);
        } else {  // the top bits_high bits under the model, the rest raw
            const std::uint32_t low_bits = k_ - bits_high;
            enc.encode_symbol(models_.position_model(k_), position >> low_bits);
            enc.write_bits(low_bits, position & ((1u << low_bits) - 1));
        }
    }

    IntegerModels models_;
    std::uint32_t k_ = 0;
};

}  // namespace lidarscout::laz
