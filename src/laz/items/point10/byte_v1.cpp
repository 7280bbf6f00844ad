// BYTE v1: chunk start state.
#include "laz/items/point10/byte_v1.hpp"

namespace lidarscout::laz::detail::point10 {

ByteDecoderV1::ByteDecoderV1(std::size_t size) : last_(size), coder_(8, static_cast<std::uint32_t>(size)) {}

void ByteDecoderV1::init(const std::uint8_t* first) {
    std::memcpy(last_.data(), first, last_.size());
    coder_.reset();
}

}  // namespace lidarscout::laz::detail::point10
