// RGB12 v2 encoder: chunk start state.
#include "laz/point10/rgb12_v2_encoder.hpp"

namespace lidarscout::laz::point10 {

Rgb12EncoderV2::Rgb12EncoderV2() = default;

void Rgb12EncoderV2::init(const std::uint8_t* first) {
    std::memcpy(last_.data(), first, kSize);
    changed_mask_.reset();
    for (auto& m : byte_models_) m.reset();
}

}  // namespace lidarscout::laz::point10
