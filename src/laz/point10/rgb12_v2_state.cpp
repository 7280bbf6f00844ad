// RGB12 v2 state: the models' construction and the reset at chunk start (out of line, away
// from the point loops).
#include "laz/point10/rgb12_v2_state.hpp"

#include <cstring>

namespace lidarscout::laz::point10 {

Rgb12StateV2::Rgb12StateV2() = default;

void Rgb12StateV2::init(const std::uint8_t* first) {
    std::memcpy(last_.data(), first, kSize);
    changed_mask_.reset();
    for (auto& m : byte_models_) m.reset();
}

}  // namespace lidarscout::laz::point10
