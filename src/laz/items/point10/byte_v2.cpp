// The BYTE item (extra bytes), version 2: the out-of-line parts of its state, decoder
// and encoder (see byte_v2.hpp).
#include "laz/items/point10/byte_v2.hpp"

#include <cstring>

namespace lidarscout::laz::detail::point10 {

// ---- State shared by the decoder and the encoder
// BYTE v2 state: the models and the reset at chunk start (out of line, away from the point
// loops).
ByteStateV2::ByteStateV2(std::size_t size) : last_(size) {
    models_.reserve(size);
    for (std::size_t i = 0; i < size; ++i) models_.emplace_back(256);
}

void ByteStateV2::init(const std::uint8_t* first) {
    std::memcpy(last_.data(), first, last_.size());
    for (auto& m : models_) m.reset();
}

}  // namespace lidarscout::laz::detail::point10
