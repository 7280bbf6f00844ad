// POINT10 v2 encoder: the (less frequent) attribute updates.
#include "laz/point10/point10_v2_encoder.hpp"

namespace lidarscout::laz::point10 {

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

}  // namespace lidarscout::laz::point10
