// WAVEPACKET14: the packet codec and its layer.
#include "laz/items/point14/wavepacket14_v3.hpp"

#include <array>

#include "laz/chunk_decoder.hpp"
#include "laz/integer_decompressor.hpp"

namespace lidarscout::laz::detail::point14 {
namespace {

// How the data offset follows from the last packet's.
enum OffsetKind : std::uint32_t { kSameOffset = 0, kAfterLast = 1, kCodedDelta = 2, kRawOffset = 3 };

struct Packet {
    std::uint8_t descriptor = 0;
    std::uint64_t offset = 0;
    std::uint32_t size = 0;
    std::int32_t return_point = 0;          // float, predicted as its bit pattern
    std::array<std::int32_t, 3> xyz{};      // floats, likewise
};

struct WavepacketCodec {
    using Value = Packet;
    struct Models {
        SymbolModel descriptor{256};
        std::array<SymbolModel, 4> offset_kind = symbol_models<4>(4);  // by the last kind
        IntegerDecompressor offset_delta{32};
        IntegerDecompressor size{32};
        IntegerDecompressor return_point{32};
        IntegerDecompressor xyz{32, 3};
        std::uint32_t last_kind = kSameOffset;
        std::int32_t last_delta = 0;
        void begin(Value&) {}
    };

    Value read(const std::uint8_t* item) const {
        Packet p;
        p.descriptor = item[0];
        p.offset = load<std::uint64_t>(item + 1);
        p.size = load<std::uint32_t>(item + 9);
        p.return_point = load<std::int32_t>(item + 13);
        for (int i = 0; i < 3; ++i) p.xyz[i] = load<std::int32_t>(item + 17 + 4 * i);
        return p;
    }
    void write(std::uint8_t* item, const Value& p) const {
        item[0] = p.descriptor;
        store(item + 1, p.offset);
        store(item + 9, p.size);
        store(item + 13, p.return_point);
        for (int i = 0; i < 3; ++i) store(item + 17 + 4 * i, p.xyz[i]);
    }

    void decode(ArithmeticDecoder& dec, Models& m, Value& v, const PointTrace&) const {
        const Packet last = v;
        v.descriptor = static_cast<std::uint8_t>(dec.decode_symbol(m.descriptor));
        m.last_kind = dec.decode_symbol(m.offset_kind[m.last_kind]);
        switch (m.last_kind) {
            case kSameOffset: v.offset = last.offset; break;
            case kAfterLast: v.offset = last.offset + last.size; break;
            case kCodedDelta:
                m.last_delta = m.offset_delta.decompress(dec, m.last_delta);
                v.offset = last.offset + static_cast<std::uint64_t>(static_cast<std::int64_t>(m.last_delta));
                break;
            default: v.offset = dec.read_int64();
        }
        v.size = static_cast<std::uint32_t>(m.size.decompress(dec, static_cast<std::int32_t>(last.size)));
        v.return_point = m.return_point.decompress(dec, last.return_point);
        for (std::uint32_t i = 0; i < 3; ++i) v.xyz[i] = m.xyz.decompress(dec, last.xyz[i], i);
    }
};

}  // namespace

void add_wavepacket14_layers(const ItemSetup& setup, std::vector<PlacedLayer>& out) {
    if (!(setup.fields & fields::kWavepacket)) return;
    out.push_back(make_layer(setup.layers[0], setup, WavepacketCodec{}, item_rule(setup.version), "wave packet"));
}

}  // namespace lidarscout::laz::detail::point14
