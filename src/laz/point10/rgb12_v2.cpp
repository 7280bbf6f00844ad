// RGB12 v2: chunk start state.
#include "laz/point10/rgb12_v2.hpp"

namespace lidarscout::laz::point10 {

Rgb12DecoderV2::Rgb12DecoderV2() = default;

void Rgb12DecoderV2::init(const std::uint8_t* first) {
    std::memcpy(last_.data(), first, kSize);
    changed_mask_.reset();
    for (auto& m : byte_models_) m.reset();
}

}  // namespace lidarscout::laz::point10
