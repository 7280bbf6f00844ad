// The RGB12 item, version 2 (point-wise chunks): one file set (rgb12_v2.hpp/.cpp) holds all of this item
// version, nothing of it lives elsewhere: its symbols, the state its decoder and encoder
// share, the decoder and the encoder.
#pragma once

#include <array>
#include <cstdint>

#include "laz/arithmetic_decoder.hpp"
#include "laz/arithmetic_encoder.hpp"
#include "laz/arithmetic_models.hpp"
#include "laz/items/item_common.hpp"

namespace lidarscout::laz::detail::point10 {

// ---- Symbols and contexts (the decoder and the encoder agree on them by construction)
// RGB12 v2: bits 0-5 of the mask flag the changed colour bytes (byte i of the item); bit 6
// says that green and blue differ from red.
namespace rgb12_v2 {
inline constexpr std::uint32_t kNotGrey = 1u << 6;
inline constexpr std::uint32_t kMaskSymbols = 128;
}  // namespace rgb12_v2

// ---- State shared by the decoder and the encoder
// The state that the RGB12 v2 decoder and encoder keep across a chunk, defined once for
// both: the last colour, the models, and the reset at chunk start.

// The decoder and the encoder derive from this.
class Rgb12StateV2 {
public:
    static constexpr std::size_t kSize = 6;

protected:
    Rgb12StateV2();

    // Starts a chunk whose first (raw) colour is at `first`.
    void init(const std::uint8_t* first);

    // Bytes of the colour: [2c] low byte, [2c + 1] high byte of channel c (r, g, b).
    std::array<std::uint8_t, 6> last_{};
    SymbolModel changed_mask_{rgb12_v2::kMaskSymbols};
    std::array<SymbolModel, 6> byte_models_{SymbolModel(256), SymbolModel(256), SymbolModel(256),
                                            SymbolModel(256), SymbolModel(256), SymbolModel(256)};
};

// ---- Decoder
// Decoder of the RGB12 item, version 2: a mask says which of the six colour bytes changed;
// red is coded against the last red, green and blue against the last value moved by red's
// change (and, for blue, green's), which captures brightness changes shared by channels.

// The state (last colour, models) is Rgb12StateV2's, shared with the encoder.
class Rgb12DecoderV2 : private Rgb12StateV2 {
public:
    using Rgb12StateV2::kSize;

    // Starts a chunk whose first (raw) colour is at `first`.
    using Rgb12StateV2::init;

    void decode(ArithmeticDecoder& dec, std::uint8_t* out) {
        const std::uint32_t mask = dec.decode_likely_symbol(changed_mask_);
        // Bytes of the colour: [2c] low byte, [2c + 1] high byte of channel c (r, g, b).
        std::array<std::uint8_t, 6> c;
        c[0] = next_byte(dec, mask, 0, last_[0]);
        c[1] = next_byte(dec, mask, 1, last_[1]);
        if (mask & kNotGrey) {
            const std::int32_t red_low = c[0] - last_[0];
            c[2] = next_byte(dec, mask, 2, clamp_byte(red_low + last_[2]));
            c[4] = next_byte(dec, mask, 4, clamp_byte((red_low + (c[2] - last_[2])) / 2 + last_[4]));
            const std::int32_t red_high = c[1] - last_[1];
            c[3] = next_byte(dec, mask, 3, clamp_byte(red_high + last_[3]));
            c[5] = next_byte(dec, mask, 5, clamp_byte((red_high + (c[3] - last_[3])) / 2 + last_[5]));
        } else {
            c[2] = c[4] = c[0];
            c[3] = c[5] = c[1];
        }
        last_ = c;
        std::memcpy(out, c.data(), kSize);
    }

private:
    static constexpr std::uint32_t kNotGrey = rgb12_v2::kNotGrey;  // green and blue differ from red

    // Byte i: the prediction plus a coded correction if its mask bit is set, else the
    // last value.
    std::uint8_t next_byte(ArithmeticDecoder& dec, std::uint32_t mask, int i, std::int32_t prediction) {
        if (!(mask & (1u << i))) return last_[i];
        return wrap_byte(static_cast<std::int32_t>(dec.decode_symbol(byte_models_[i])) + prediction);
    }
};

// ---- Encoder
// Encoder of the RGB12 item, version 2: the inverse of Rgb12DecoderV2. The mask flags the
// colour bytes that changed (and whether the colour is grey); changed bytes are coded as
// differences to the same predictions the decoder makes.

// The state (last colour, models) is Rgb12StateV2's, shared with the decoder.
class Rgb12EncoderV2 : private Rgb12StateV2 {
public:
    using Rgb12StateV2::kSize;

    // Starts a chunk whose first (raw) colour is at `first`.
    using Rgb12StateV2::init;

    void encode(ArithmeticEncoder& enc, const std::uint8_t* item) {
        // Bytes of the colour: [2c] low byte, [2c + 1] high byte of channel c (r, g, b).
        std::array<std::uint8_t, 6> c;
        std::memcpy(c.data(), item, kSize);
        const std::uint32_t mask = change_mask(c);
        enc.encode_symbol(changed_mask_, mask);
        put_byte(enc, mask, 0, c, last_[0]);
        put_byte(enc, mask, 1, c, last_[1]);
        if (mask & rgb12_v2::kNotGrey) {
            const std::int32_t red_low = c[0] - last_[0];
            put_byte(enc, mask, 2, c, clamp_byte(red_low + last_[2]));
            put_byte(enc, mask, 4, c, clamp_byte((red_low + (c[2] - last_[2])) / 2 + last_[4]));
            const std::int32_t red_high = c[1] - last_[1];
            put_byte(enc, mask, 3, c, clamp_byte(red_high + last_[3]));
            put_byte(enc, mask, 5, c, clamp_byte((red_high + (c[3] - last_[3])) / 2 + last_[5]));
        }
        last_ = c;
    }

private:
    std::uint32_t change_mask(const std::array<std::uint8_t, 6>& c) const {
        std::uint32_t mask = 0;
        for (std::uint32_t i = 0; i < kSize; ++i) mask |= std::uint32_t{c[i] != last_[i]} << i;
        const bool grey = c[0] == c[2] && c[0] == c[4] && c[1] == c[3] && c[1] == c[5];
        return grey ? mask : mask | rgb12_v2::kNotGrey;
    }

    // Byte i as a difference to `prediction`, if its mask bit is set.
    void put_byte(ArithmeticEncoder& enc, std::uint32_t mask, int i, const std::array<std::uint8_t, 6>& c,
                  std::int32_t prediction) {
        if (mask & (1u << i)) enc.encode_symbol(byte_models_[i], wrap_byte(c[i] - prediction));
    }
};

}  // namespace lidarscout::laz::detail::point10
