// BYTE v2 state: the models and the reset at chunk start (out of line, away from the point
// loops).
#include "laz/point10/byte_v2_state.hpp"

#include <cstring>

namespace lidarscout::laz::point10 {

ByteStateV2::ByteStateV2(std::size_t size) : last_(size) {
    models_.reserve(size);
    for (std::size_t i = 0; i < size; ++i) models_.emplace_back(256);
}

void ByteStateV2::init(const std::uint8_t* first) {
    std::memcpy(last_.data(), first, last_.size());
    for (auto& m : models_) m.reset();
}

}  // namespace lidarscout::laz::point10
