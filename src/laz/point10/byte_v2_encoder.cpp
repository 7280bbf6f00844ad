// BYTE v2 encoder: models and chunk start state.
#include "laz/point10/byte_v2_encoder.hpp"

namespace lidarscout::laz::point10 {

ByteEncoderV2::ByteEncoderV2(std::size_t size) : last_(size) {
    models_.reserve(size);
    for (std::size_t i = 0; i < size; ++i) models_.emplace_back(256);
}

void ByteEncoderV2::init(const std::uint8_t* first) {
    std::memcpy(last_.data(), first, last_.size());
    for (auto& m : models_) m.reset();
}

}  // namespace lidarscout::laz::point10
