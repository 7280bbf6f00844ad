// Decoder of the RGB12 item, version 2: a mask says which of the six colour bytes changed;
// red is coded against the last red, green and blue against the last value moved by red's
// change (and, for blue, green's), which captures brightness changes shared by channels.
#pragma once

#include <array>
#include <cstdint>

#include "laz/arithmetic_decoder.hpp"
#include "laz/point10/item_common.hpp"
#include "laz/point10/rgb12_v2_state.hpp"
#include "laz/point10/symbols_v2.hpp"

namespace lidarscout::laz::point10 {

// The state (last colour, models) is Rgb12StateV2's, shared with the encoder.
class Rgb12DecoderV2 : private Rgb12StateV2 {
public:
    using Rgb12StateV2::kSize;

    // Starts a chunk whose first (raw) colour is at `first`.
    using Rgb12StateV2::init;

    void decode(ArithmeticDecoder& dec, std::uint8_t* out) {
        const std::uint32_t mask = dec.decode_symbol(changed_mask_);
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

}  // namespace lidarscout::laz::point10
