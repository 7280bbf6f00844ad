// The POINT10 item, version 2 (LAS formats 0-5 as LASzip 2.x+ writes them): one file set
// (point10_v2.hpp/.cpp) holds all of this item version, nothing of it lives elsewhere: its symbols,
// the state its decoder and encoder share, the decoder and the encoder.
#pragma once

#include <array>
#include <cstdint>

#include "laz/arithmetic_decoder.hpp"
#include "laz/arithmetic_encoder.hpp"
#include "laz/arithmetic_models.hpp"
#include "laz/integer_compressor.hpp"
#include "laz/integer_decompressor.hpp"
#include "laz/items/item_common.hpp"
#include "laz/items/point10/point10_record.hpp"

namespace lidarscout::laz::detail::point10 {

// ---- Symbols and contexts (the decoder and the encoder agree on them by construction)
// Symbols of the POINT10 v2 change mask, shared by the decoder and the encoder.
namespace point10_v2 {
inline constexpr std::uint32_t kChangedPointSource = 1u << 0;
inline constexpr std::uint32_t kChangedUserData = 1u << 1;
inline constexpr std::uint32_t kChangedScanAngle = 1u << 2;
inline constexpr std::uint32_t kChangedClassification = 1u << 3;
inline constexpr std::uint32_t kChangedIntensity = 1u << 4;
inline constexpr std::uint32_t kChangedReturnFlags = 1u << 5;
inline constexpr std::uint32_t kChangeMaskSymbols = 64;
}  // namespace point10_v2

// ---- State shared by the decoder and the encoder
// The state that the POINT10 v2 decoder and encoder keep across a chunk, defined once for
// both so they start every chunk alike and predict from the same values: the last point,
// running medians of the X/Y deltas and the last intensity and Z per return context, the
// models, and the reset at chunk start. The integer coders are IntegerDecompressor in the
// decoder and IntegerCompressor in the encoder.

// Context tables indexed [number of returns][return number]: a return "kind" (16 values,
// for intensity and XY medians) and a return "level" (8 values, for Z). Out-of-spec
// combinations get contexts of their own. Defined in point10_v2.cpp.
extern const std::uint8_t kReturnKind[8][8];
extern const std::uint8_t kReturnLevel[8][8];

// The decoder and the encoder derive from this; `IntegerCoder` is IntegerDecompressor or
// IntegerCompressor.
template <class IntegerCoder>
class Point10StateV2 {
protected:
    // Starts a chunk whose first (raw) POINT10 item is `first`: the last point is `first`,
    // everything else is back in its start state. Out of line (point10_v2.cpp), as it
    // runs once a chunk, away from the point loops.
    void init(const std::uint8_t* first);

    Point10Record last_;
    std::array<RunningMedian5, 16> x_median_;
    std::array<RunningMedian5, 16> y_median_;
    std::array<std::uint16_t, 16> last_intensity_{};
    std::array<std::int32_t, 8> last_z_{};

    SymbolModel changed_mask_{point10_v2::kChangeMaskSymbols};
    ByteModelsByPrevious return_flags_models_;
    ByteModelsByPrevious classification_models_;
    ByteModelsByPrevious user_data_models_;
    std::array<SymbolModel, 2> scan_angle_models_{SymbolModel(256), SymbolModel(256)};
    IntegerCoder intensity_{16, 4};
    IntegerCoder point_source_{16, 1};
    IntegerCoder dx_{32, 2};
    IntegerCoder dy_{32, 22};
    IntegerCoder z_{32, 20};

private:
    void reset_predictions();
    void reset_models();
};

// ---- Decoder
// Decoder of the POINT10 item, version 2 (LAS formats 0-5 as LASzip 2.x+ writes them):
// a 64-symbol mask says which attributes changed; X and Y deltas are predicted by running
// medians kept per return context, Z by the last height per return level.

// The state (last point, medians, models) is Point10StateV2's, shared with the encoder.
class Point10DecoderV2 : private Point10StateV2<IntegerDecompressor> {
public:
    Point10DecoderV2();

    // Starts a chunk whose first (raw) POINT10 item is `first`.
    void init(const std::uint8_t* first);

    void decode(ArithmeticDecoder& dec, std::uint8_t* out) {
        const std::uint32_t changed = dec.decode_likely_symbol(changed_mask_);
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

// ---- Encoder
// Encoder of the POINT10 item, version 2: the inverse of Point10DecoderV2, with the same
// change mask, return contexts, running medians and models (the state is Point10StateV2,
// shared with the decoder), so its output is byte-identical to LASzip's.
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

}  // namespace lidarscout::laz::detail::point10
