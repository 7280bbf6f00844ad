// BYTE14 encoding: the per-byte codec.
#include "laz/point14/byte14_v3_encoder.hpp"

namespace lidarscout::laz::point14 {
namespace {

struct ByteEncoder {
    using Value = std::uint8_t;
    struct Models {
        SymbolModel difference{256};
        void begin(Value&) {}
    };
    std::size_t offset = 0;  // the byte's position in the item

    Value read(const std::uint8_t* item) const { return item[offset]; }
    bool encode(ArithmeticEncoder& enc, Models& m, Value& last, Value now, const PointTrace&) const {
        enc.encode_symbol(m.difference, wrap_byte(now - last));
        const bool changed = now != last;
        last = now;
        return changed;
    }
};

}  // namespace

void add_byte14_encoders(const ItemEncodeSetup& setup, std::size_t size,
                         std::vector<std::unique_ptr<LayerEncoder>>& out) {
    for (std::size_t i = 0; i < size; ++i) {
        out.push_back(make_layer_encoder(setup, ByteEncoder{i}, ContextRule::kItemV3));
    }
}

}  // namespace lidarscout::laz::point14
