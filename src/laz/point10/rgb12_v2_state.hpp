// The state that the RGB12 v2 decoder and encoder keep across a chunk, defined once for
// both: the last colour, the models, and the reset at chunk start.
#pragma once

#include <array>
#include <cstdint>

#include "laz/arithmetic_models.hpp"
#include "laz/point10/symbols_v2.hpp"

namespace lidarscout::laz::point10 {

// The decoder and the encoder derive from this.
class Rgb12StateV2 {
public:
    static constexpr std::size_t kSize = 6;

protected:
    Rgb12StateV2();

    // Starts a chunk whose first (raw) colour is at `first`.
    void init(const std::uint8_t* first);

    // Bytes of the colour: [2c] low byte, [2c + 1] high byte of channel c (r, g, b).
    std::array<std::uint8_t, 6> last_{};
    SymbolModel changed_mask_{rgb12_v2::kMaskSymbols};
    std::array<SymbolModel, 6> byte_models_{SymbolModel(256), SymbolModel(256), SymbolModel(256),
                                            SymbolModel(256), SymbolModel(256), SymbolModel(256)};
};

}  // namespace lidarscout::laz::point10
