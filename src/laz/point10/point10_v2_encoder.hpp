// Encoder of the POINT10 item, version 2: the inverse of Point10DecoderV2, with the same
// change mask, return contexts, running medians and models (the state is Point10StateV2,
// shared with the decoder), so its output is byte-identical to LASzip's.
#pragma once

#include <cstdint>

#include "laz/arithmetic_encoder.hpp"
#include "laz/integer_compressor.hpp"
#include "laz/point10/item_common.hpp"
#include "laz/point10/point10_record.hpp"
#include "laz/point10/point10_v2_state.hpp"
#include "laz/point10/symbols_v2.hpp"

namespace lidarscout::laz::point10 {

class Point10EncoderV2 : private Point10StateV2<IntegerCompressor> {
public:
    Point10EncoderV2();

    // Starts a chunk whose first (raw) POINT10 item is `first`.
    using Point10StateV2::init;

    void encode(ArithmeticEncoder& enc, const std::uint8_t* item) {
        const Point10Record point = Point10Record::load(item);
        const std::uint32_t n = point.number_of_returns();
        const std::uint32_t r = point.return_number();
        const std::uint32_t kind = kReturnKind[n][r];

        const std::uint32_t changed = change_mask(point, kind);
        enc.encode_symbol(changed_mask_, changed);
        if (changed != 0) encode_attributes(enc, point, changed, kind);

        const std::uint32_t single = n == 1;
        const std::int32_t dx = subtract_wrapping(point.x, last_.x);
        dx_.compress(enc, x_median_[kind].median(), dx, single);
        x_median_[kind].add(dx);

        std::uint32_t k = dx_.last_class();
        const std::int32_t dy = subtract_wrapping(point.y, last_.y);
        dy_.compress(enc, y_median_[kind].median(), dy, single + (k < 20 ? k & ~1u : 20));
        y_median_[kind].add(dy);

        k = (dx_.last_class() + dy_.last_class()) / 2;
        const std::uint32_t level = kReturnLevel[n][r];
        z_.compress(enc, last_z_[level], point.z, single + (k < 18 ? k & ~1u : 18));
        last_z_[level] = point.z;

        last_ = point;
    }

private:
    static std::int32_t subtract_wrapping(std::int32_t a, std::int32_t b) {
        return static_cast<std::int32_t>(static_cast<std::uint32_t>(a) - static_cast<std::uint32_t>(b));
    }

    // Which attributes (other than XYZ) differ from the last point; intensity is compared
    // with the last intensity of the point's return kind.
    std::uint32_t change_mask(const Point10Record& point, std::uint32_t kind) const {
        using namespace point10_v2;
        return (point.return_flags != last_.return_flags ? kChangedReturnFlags : 0u) |
               (point.intensity != last_intensity_[kind] ? kChangedIntensity : 0u) |
               (point.classification != last_.classification ? kChangedClassification : 0u) |
               (point.scan_angle != last_.scan_angle ? kChangedScanAngle : 0u) |
               (point.user_data != last_.user_data ? kChangedUserData : 0u) |
               (point.point_source != last_.point_source ? kChangedPointSource : 0u);
    }

    // Everything but XYZ, as flagged in the change mask.
    void encode_attributes(ArithmeticEncoder& enc, const Point10Record& point, std::uint32_t changed,
                           std::uint32_t kind);
};

}  // namespace lidarscout::laz::point10
