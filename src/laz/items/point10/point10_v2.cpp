// The POINT10 item, version 2: the out-of-line parts of its state, decoder
// and encoder (see point10_v2.hpp).
#include "laz/items/point10/point10_v2.hpp"

#include "laz/integer_compressor.hpp"
#include "laz/integer_decompressor.hpp"

namespace lidarscout::laz::detail::point10 {

// ---- State shared by the decoder and the encoder
// POINT10 v2 state: the return-kind context tables and the reset at chunk start, shared by the
// decoder's and the encoder's integer coders (neither defines anything the other uses).

// Well-formed pairs (1 <= r <= n <= 5) are numbered 0..14 for the kind and by n - r for
// the level; the rest of each table spreads the odd pairs over the remaining contexts.
const std::uint8_t kReturnKind[8][8] = {
    {15, 14, 13, 12, 11, 10, 9, 8},  {14, 0, 1, 3, 6, 10, 10, 9},    {13, 1, 2, 4, 7, 11, 11, 10},
    {12, 3, 4, 5, 8, 12, 12, 11},    {11, 6, 7, 8, 9, 13, 13, 12},   {10, 10, 11, 12, 13, 14, 14, 13},
    {9, 10, 11, 12, 13, 14, 15, 14}, {8, 9, 10, 11, 12, 13, 14, 15},
};

const std::uint8_t kReturnLevel[8][8] = {
    {0, 1, 2, 3, 4, 5, 6, 7}, {1, 0, 1, 2, 3, 4, 5, 6}, {2, 1, 0, 1, 2, 3, 4, 5}, {3, 2, 1, 0, 1, 2, 3, 4},
    {4, 3, 2, 1, 0, 1, 2, 3}, {5, 4, 3, 2, 1, 0, 1, 2}, {6, 5, 4, 3, 2, 1, 0, 1}, {7, 6, 5, 4, 3, 2, 1, 0},
};

template <class IntegerCoder>
void Point10StateV2<IntegerCoder>::init(const std::uint8_t* first) {
    reset_predictions();
    reset_models();
    last_ = Point10Record::load(first);
}

template <class IntegerCoder>
void Point10StateV2<IntegerCoder>::reset_predictions() {
    for (auto& m : x_median_) m.reset();
    for (auto& m : y_median_) m.reset();
    last_intensity_.fill(0);
    last_z_.fill(0);
}

template <class IntegerCoder>
void Point10StateV2<IntegerCoder>::reset_models() {
    changed_mask_.reset();
    return_flags_models_.reset();
    classification_models_.reset();
    user_data_models_.reset();
    for (auto& m : scan_angle_models_) m.reset();
    intensity_.reset();
    point_source_.reset();
    dx_.reset();
    dy_.reset();
    z_.reset();
}

template class Point10StateV2<IntegerDecompressor>;
template class Point10StateV2<IntegerCompressor>;

// ---- Decoder
// POINT10 v2 decoder: the context tables, the chunk start and the (less frequent) attribute
// updates.
using namespace point10_v2;  // the change mask bits

Point10DecoderV2::Point10DecoderV2() = default;

void Point10DecoderV2::init(const std::uint8_t* first) {
    Point10StateV2::init(first);
    // The decoder starts the chunk's intensity at 0, as LASzip's reader does: at a point
    // whose change mask is 0 it repeats last_.intensity, and the encoder leaves the mask 0
    // only where the intensity equals last_intensity_ of the point's kind, which is 0 at
    // chunk start. The encoder never reads last_.intensity and keeps the raw value there
    // (as LASzip's writer does); the difference shows in no output.
    last_.intensity = 0;
}

[[gnu::flatten]] void Point10DecoderV2::decode_attributes(ArithmeticDecoder& dec, std::uint32_t changed) {
    if (changed & kChangedReturnFlags) {
        last_.return_flags = return_flags_models_.decode(dec, last_.return_flags);
    }
    const std::uint32_t kind = kReturnKind[last_.number_of_returns()][last_.return_number()];
    if (changed & kChangedIntensity) {
        last_.intensity = static_cast<std::uint16_t>(
            intensity_.decompress(dec, last_intensity_[kind], kind < 3 ? kind : 3));
        last_intensity_[kind] = last_.intensity;
    } else {
        last_.intensity = last_intensity_[kind];
    }
    if (changed & kChangedClassification) {
        last_.classification = classification_models_.decode(dec, last_.classification);
    }
    if (changed & kChangedScanAngle) {
        const std::uint32_t delta = dec.decode_symbol(scan_angle_models_[last_.scan_direction()]);
        last_.scan_angle = wrap_byte(static_cast<std::int32_t>(delta + last_.scan_angle));
    }
    if (changed & kChangedUserData) {
        last_.user_data = user_data_models_.decode(dec, last_.user_data);
    }
    if (changed & kChangedPointSource) {
        last_.point_source = static_cast<std::uint16_t>(point_source_.decompress(dec, last_.point_source));
    }
}

// ---- Encoder
// POINT10 v2 encoder: the (less frequent) attribute updates.
using namespace point10_v2;  // the change mask bits

Point10EncoderV2::Point10EncoderV2() = default;

[[gnu::flatten]] void Point10EncoderV2::encode_attributes(ArithmeticEncoder& enc, const Point10Record& point,
                                                          std::uint32_t changed, std::uint32_t kind) {
    if (changed & kChangedReturnFlags) {
        enc.encode_symbol(return_flags_models_.model_after(last_.return_flags), point.return_flags);
    }
    if (changed & kChangedIntensity) {
        intensity_.compress(enc, last_intensity_[kind], point.intensity, kind < 3 ? kind : 3);
        last_intensity_[kind] = point.intensity;
    }
    if (changed & kChangedClassification) {
        enc.encode_symbol(classification_models_.model_after(last_.classification), point.classification);
    }
    if (changed & kChangedScanAngle) {
        enc.encode_symbol(scan_angle_models_[point.scan_direction()],
                          wrap_byte(std::int32_t{point.scan_angle} - last_.scan_angle));
    }
    if (changed & kChangedUserData) {
        enc.encode_symbol(user_data_models_.model_after(last_.user_data), point.user_data);
    }
    if (changed & kChangedPointSource) {
        point_source_.compress(enc, last_.point_source, point.point_source);
    }
}

}  // namespace lidarscout::laz::detail::point10
