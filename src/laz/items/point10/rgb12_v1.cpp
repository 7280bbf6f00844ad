// RGB12 v1: chunk start state.
#include "laz/items/point10/rgb12_v1.hpp"

namespace lidarscout::laz::detail::point10 {

Rgb12DecoderV1::Rgb12DecoderV1() = default;

void Rgb12DecoderV1::init(const std::uint8_t* first) {
    std::memcpy(last_.data(), first, kSize);
    changed_mask_.reset();
    byte_coder_.reset();
}

}  // namespace lidarscout::laz::detail::point10
