// POINT10 v2 encoder: chunk start state and the (less frequent) attribute updates.
#include "laz/point10/point10_v2_encoder.hpp"

namespace lidarscout::laz::point10 {

using namespace point10_v2;  // the change mask bits

Point10EncoderV2::Point10EncoderV2() = default;

void Point10EncoderV2::init(const std::uint8_t* first) {
    for (auto& m : x_median_) m.reset();
    for (auto& m : y_median_) m.reset();
    last_intensity_.fill(0);
    last_z_.fill(0);

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

    last_ = Point10Record::load(first);
}

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
