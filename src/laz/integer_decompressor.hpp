// Decoding side of LASzip's integer coding: reads a corrector under IntegerModels and adds
// it to a prediction, wrapping within the coded range. Item decoders keep one of these per
// field (e.g. 32 bits for coordinates, 16 for intensity) and reset it at every chunk.
#pragma once

#include <cstdint>

#include "laz/arithmetic_decoder.hpp"
#include "laz/integer_models.hpp"

namespace lidarscout::laz {

class IntegerDecompressor {
public:
    // See IntegerModels for the parameters; the defaults are LASzip's.
    explicit IntegerDecompressor(std::uint32_t bits = 16, std::uint32_t contexts = 1,
                                 std::uint32_t bits_high = 8, std::uint32_t range = 0)
        : models_(bits, contexts, bits_high, range) {}

    // Back to the start state (at the start of every chunk).
    void reset() { models_.reset(); }

    // The value coded after `prediction` in `context` (< contexts()).
    std::int32_t decompress(ArithmeticDecoder& dec, std::int32_t prediction, std::uint32_t context = 0) {
        const std::uint32_t range = models_.corrector_range();
        std::uint32_t value = static_cast<std::uint32_t>(prediction) + read_corrector(dec, context);
        if (static_cast<std::int32_t>(value) < 0) {
            value += range;
        } else if (value >= range) {
            value -= range;  // (a range of 0, i.e. 2^32, leaves the wrapped sum as it is)
        }
        return static_cast<std::int32_t>(value);
    }

    // Size class k of the last decoded corrector (item decoders use it as a context).
    std::uint32_t last_class() const { return k_; }
    std::uint32_t contexts() const { return models_.contexts(); }

private:
    // The corrector as a two's-complement bit pattern.
    std::uint32_t read_corrector(ArithmeticDecoder& dec, std::uint32_t context) {
        k_ = dec.decode_symbol(models_.class_model(context));
        if (k_ == 0) return dec.decode_bit(models_.unit_model());  // 0 or 1
        if (k_ >= 32) return static_cast<std::uint32_t>(models_.corrector_min());

        std::uint32_t c = dec.decode_symbol(models_.position_model(k_));
        if (k_ > models_.bits_high()) {  // the low bits of wide classes are raw
            const std::uint32_t low_bits = k_ - models_.bits_high();
            c = (c << low_bits) | dec.read_bits(low_bits);
        }
        // Class k holds [-(2^k - 1), -2^(k-1)] (coded as 0 .. 2^(k-1)-1) and
        // [2^(k-1) + 1, 2^k] (coded as 2^(k-1) .. 2^k - 1).
        const std::uint32_t half = 1u << (k_ - 1);
        return c >= half ? c + 1 : c - ((half << 1) - 1);
    }

    IntegerModels models_;
    std::uint32_t k_ = 0;
};

}  // namespace lidarscout::laz
