// Decoder of the POINT10 item, version 2 (LAS formats 0-5 as LASzip 2.x+ writes them):
// a 64-symbol mask says which attributes changed; X and Y deltas are predicted by running
// medians kept per return context, Z by the last height per return level.
#pragma once

#include <cstdint>

#include "laz/arithmetic_decoder.hpp"
#include "laz/integer_decompressor.hpp"
#include "laz/point10/item_common.hpp"
#include "laz/point10/point10_record.hpp"
#include "laz/point10/point10_v2_state.hpp"

namespace lidarscout::laz::point10 {

// The state (last point, medians, models) is Point10StateV2's, shared with the encoder.
class Point10DecoderV2 : private Point10StateV2<IntegerDecompressor> {
public:
    Point10DecoderV2();

    // Starts a chunk whose first (raw) POINT10 item is `first`.
    void init(const std::uint8_t* first);

    void decode(ArithmeticDecoder& dec, std::uint8_t* out) {
        const std::uint32_t changed = dec.decode_symbol(changed_mask_);
        if (changed != 0) decode_attributes(dec, changed);
        const std::uint32_t n = last_.number_of_returns();
        const std::uint32_t r = last_.return_number();
        const std::uint32_t kind = kReturnKind[n][r];
        const std::uint32_t single = n == 1;

        const std::int32_t dx = dx_.decompress(dec, x_median_[kind].median(), single);
        last_.x = add_wrapping(last_.x, dx);
        x_median_[kind].add(dx);

        std::uint32_t k = dx_.last_class();
        const std::int32_t dy = dy_.decompress(dec, y_median_[kind].median(), single + (k < 20 ? k & ~1u : 20));
        last_.y = add_wrapping(last_.y, dy);
        y_median_[kind].add(dy);

        k = (dx_.last_class() + dy_.last_class()) / 2;
        const std::uint32_t level = kReturnLevel[n][r];
        last_.z = z_.decompress(dec, last_z_[level], single + (k < 18 ? k & ~1u : 18));
        last_z_[level] = last_.z;

        last_.store(out);
    }

private:
    // Everything but XYZ, as flagged in the change mask.
    void decode_attributes(ArithmeticDecoder& dec, std::uint32_t changed);
};

}  // namespace lidarscout::laz::point10
