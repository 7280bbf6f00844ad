// Decoder of the POINT10 item, version 1 (the first LASzip releases): XYZ come first,
// X and Y deltas predicted by the median of the last three, Z by the last Z; then a
// 64-symbol mask says which other attributes changed.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>

#include "laz/arithmetic_decoder.hpp"
#include "laz/integer_decompressor.hpp"
#include "laz/items/item_common.hpp"
#include "laz/items/point10/point10_record.hpp"

namespace lidarscout::laz::detail::point10 {

// The last three values of a delta, in a ring, and their median.
class LastThree {
public:
    void reset() {
        values_ = {};
        next_ = 0;
    }
    std::int32_t median() const {
        const auto [lo, hi] = std::minmax(values_[0], values_[1]);
        return std::clamp(values_[2], lo, hi);
    }
    void add(std::int32_t v) {
        values_[next_] = v;
        next_ = next_ == 2 ? 0 : next_ + 1;
    }

private:
    std::array<std::int32_t, 3> values_{};
    std::uint32_t next_ = 0;
};

class Point10DecoderV1 {
public:
    Point10DecoderV1();

    // Starts a chunk whose first (raw) POINT10 item is `first`.
    void init(const std::uint8_t* first);

    void decode(ArithmeticDecoder& dec, std::uint8_t* out) {
        const std::int32_t dx = dx_.decompress(dec, x_deltas_.median());
        last_.x = add_wrapping(last_.x, dx);
        std::uint32_t k = dx_.last_class();
        const std::int32_t dy = dy_.decompress(dec, y_deltas_.median(), k < 19 ? k : 19);
        last_.y = add_wrapping(last_.y, dy);
        k = (k + dy_.last_class()) / 2;
        last_.z = z_.decompress(dec, last_.z, k < 19 ? k : 19);

        const std::uint32_t changed = dec.decode_symbol(changed_mask_);
        if (changed != 0) decode_attributes(dec, changed, k);

        x_deltas_.add(dx);
        y_deltas_.add(dy);
        last_.store(out);
    }

private:
    // Everything but XYZ, as flagged in the change mask; `xyz_class` is the size class
    // that chose Z's context.
    void decode_attributes(ArithmeticDecoder& dec, std::uint32_t changed, std::uint32_t xyz_class);

    Point10Record last_;
    LastThree x_deltas_;
    LastThree y_deltas_;

    SymbolModel changed_mask_{64};
    ByteModelsByPrevious return_flags_models_;
    ByteModelsByPrevious classification_models_;
    ByteModelsByPrevious user_data_models_;
    IntegerDecompressor dx_{32, 1};
    IntegerDecompressor dy_{32, 20};
    IntegerDecompressor z_{32, 20};
    IntegerDecompressor intensity_{16, 1};
    IntegerDecompressor scan_angle_{8, 2};
    IntegerDecompressor point_source_{16, 1};
};

}  // namespace lidarscout::laz::detail::point10
