// The state that the BYTE v2 (extra bytes) decoder and encoder keep across a chunk, defined
// once for both: the last value and the model of every byte, and the reset at chunk start.
#pragma once

#include <cstdint>
#include <vector>

#include "laz/arithmetic_models.hpp"

namespace lidarscout::laz::point10 {

// The decoder and the encoder derive from this.
class ByteStateV2 {
protected:
    // `size`: bytes in the item (at least 1).
    explicit ByteStateV2(std::size_t size);

    // Starts a chunk whose first (raw) bytes are at `first`.
    void init(const std::uint8_t* first);

    std::vector<std::uint8_t> last_;
    std::vector<SymbolModel> models_;
};

}  // namespace lidarscout::laz::point10
