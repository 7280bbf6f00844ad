// The RGB12 item, version 2: the out-of-line parts of its state, decoder
// and encoder (see rgb12_v2.hpp).
#include "laz/items/point10/rgb12_v2.hpp"

#include <cstring>

namespace lidarscout::laz::detail::point10 {

// ---- State shared by the decoder and the encoder
// RGB12 v2 state: the models' construction and the reset at chunk start (out of line, away
// from the point loops).
Rgb12StateV2::Rgb12StateV2() = default;

void Rgb12StateV2::init(const std::uint8_t* first) {
    std::memcpy(last_.data(), first, kSize);
    changed_mask_.reset();
    for (auto& m : byte_models_) m.reset();
}

}  // namespace lidarscout::laz::detail::point10
