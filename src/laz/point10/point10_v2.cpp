// POINT10 v2 decoder: the context tables, the chunk start and the (less frequent) attribute
// updates.
#include "laz/point10/point10_v2.hpp"

#include "laz/point10/symbols_v2.hpp"

namespace lidarscout::laz::point10 {

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

}  // namespace lidarscout::laz::point10
