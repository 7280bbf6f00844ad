// Decoder of the POINT10 item, version 2 (LAS formats 0-5 as LASzip 2.x+ writes them):
// a 64-symbol mask says which attributes changed; X and Y deltas are predicted by running
// medians kept per return context, Z by the last height per return level.
#pragma once

#include <array>
#include <cstdint>

#include "laz/arithmetic_decoder.hpp"
#include "laz/integer_decompressor.hpp"
#include "laz/point10/item_common.hpp"
#include "laz/point10/point10_record.hpp"

namespace lidarscout::laz::point10 {

// Median of the last five values, updated in the LAZ way: the window is a sorted list of
// five, and each new value evicts the largest or the smallest, alternating whenever the
// new value lands on the side being evicted from.
class RunningMedian5 {
public:
    void reset() {
        sorted_ = {};
        evict_largest_ = true;
    }
    std::int32_t median() const { return sorted_[2]; }

    void add(std::int32_t v) {
        if (evict_largest_) {
            const bool upper = v >= sorted_[2];
            int i = 4;
            for (; i > 0 && v < sorted_[i - 1]; --i) sorted_[i] = sorted_[i - 1];
            sorted_[i] = v;
            if (upper) evict_largest_ = false;
        } else {
            const bool lower = v <= sorted_[2];
            int i = 0;
            for (; i < 4 && sorted_[i + 1] < v; ++i) sorted_[i] = sorted_[i + 1];
            sorted_[i] = v;
            if (lower) evict_largest_ = true;
        }
    }

private:
    std::array<std::int32_t, 5> sorted_{};
    bool evict_largest_ = true;
};

// Context tables indexed [number of returns][return number]: a return "kind" (16 values,
// for intensity and XY medians) and a return "level" (8 values, for Z). Out-of-spec
// combinations get contexts of their own.
extern const std::uint8_t kReturnKind[8][8];
extern const std::uint8_t kReturnLevel[8][8];

class Point10DecoderV2 {
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

    Point10Record last_;
    std::array<RunningMedian5, 16> x_median_;
    std::array<RunningMedian5, 16> y_median_;
    std::array<std::uint16_t, 16> last_intensity_{};
    std::array<std::int32_t, 8> last_z_{};

    SymbolModel changed_mask_{64};
    ByteModelsByPrevious return_flags_models_;
    ByteModelsByPrevious classification_models_;
    ByteModelsByPrevious user_data_models_;
    std::array<SymbolModel, 2> scan_angle_models_{SymbolModel(256), SymbolModel(256)};
    IntegerDecompressor intensity_{16, 4};
    IntegerDecompressor point_source_{16, 1};
    IntegerDecompressor dx_{32, 2};
    IntegerDecompressor dy_{32, 22};
    IntegerDecompressor z_{32, 20};
};

}  // namespace lidarscout::laz::point10
