// Encoder of the RGB12 item, version 2: the inverse of Rgb12DecoderV2. The mask flags the
// colour bytes that changed (and whether the colour is grey); changed bytes are coded as
// differences to the same predictions the decoder makes.
#pragma once

#include <array>
#include <cstdint>

#include "laz/arithmetic_encoder.hpp"
#include "laz/point10/item_common.hpp"
#include "laz/point10/rgb12_v2_state.hpp"
#include "laz/point10/symbols_v2.hpp"

namespace lidarscout::laz::point10 {

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

}  // namespace lidarscout::laz::point10
