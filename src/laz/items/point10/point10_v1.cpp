// POINT10 v1: chunk start state and the attribute updates after XYZ.
#include "laz/items/point10/point10_v1.hpp"

namespace lidarscout::laz::detail::point10 {
namespace {

// Bits of the change mask (v1 order: intensity before the return flags).
constexpr std::uint32_t kChangedPointSource = 1u << 0;
constexpr std::uint32_t kChangedUserData = 1u << 1;
constexpr std::uint32_t kChangedScanAngle = 1u << 2;
constexpr std::uint32_t kChangedClassification = 1u << 3;
constexpr std::uint32_t kChangedReturnFlags = 1u << 4;
constexpr std::uint32_t kChangedIntensity = 1u << 5;

}  // namespace

Point10DecoderV1::Point10DecoderV1() = default;

void Point10DecoderV1::init(const std::uint8_t* first) {
    x_deltas_.reset();
    y_deltas_.reset();
    changed_mask_.reset();
    return_flags_models_.reset();
    classification_models_.reset();
    user_data_models_.reset();
    dx_.reset();
    dy_.reset();
    z_.reset();
    intensity_.reset();
    scan_angle_.reset();
    point_source_.reset();
    last_ = Point10Record::load(first);
}

void Point10DecoderV1::decode_attributes(ArithmeticDecoder& dec, std::uint32_t changed,
                                         std::uint32_t xyz_class) {
    if (changed & kChangedIntensity) {
        last_.intensity = static_cast<std::uint16_t>(intensity_.decompress(dec, last_.intensity));
    }
    if (changed & kChangedReturnFlags) {
        last_.return_flags = return_flags_models_.decode(dec, last_.return_flags);
    }
    if (changed & kChangedClassification) {
        last_.classification = classification_models_.decode(dec, last_.classification);
    }
    if (changed & kChangedScanAngle) {
        last_.scan_angle =
            static_cast<std::uint8_t>(scan_angle_.decompress(dec, last_.scan_angle, xyz_class < 3 ? 1 : 0));
    }
    if (changed & kChangedUserData) {
        last_.user_data = user_data_models_.decode(dec, last_.user_data);
    }
    if (changed & kChangedPointSource) {
        last_.point_source = static_cast<std::uint16_t>(point_source_.decompress(dec, last_.point_source));
    }
}

}  // namespace lidarscout::laz::detail::point10
