// Building blocks of the item encoders of layered LAZ chunks, the mirror of the decoder above:
// every layer is coded into its own arithmetic-coded stream by its own pass over a block of
// points, after the POINT14 returns/XY/Z pass has left a PointTrace per point. Contexts per
// scanner channel are kept with the decoder's ChannelContexts, so both sides pick the same
// context and the same last value at every point (version 3 quirk included).
//
// A layer whose field never changes in the chunk is stored empty, as LASzip does: its stream
// is still coded (the models must adapt as LASzip's do), then dropped.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <utility>
#include <vector>

#include "laz/arithmetic_encoder.hpp"
#include "laz/items/point14/layer_common.hpp"

namespace lidarscout::laz::detail::point14 {

// The encoder of one layer. `item` pointers address the item's bytes inside a record;
// consecutive records are `stride` bytes apart.
class LayerEncoder {
public:
    LayerEncoder() { encoder_.start(bytes_); }
    virtual ~LayerEncoder() = default;
    LayerEncoder(const LayerEncoder&) = delete;
    LayerEncoder& operator=(const LayerEncoder&) = delete;

    // Codes the next `count` points; trace[i] and item + i * stride belong to point i.
    virtual void encode(const PointTrace* trace, std::size_t count, const std::uint8_t* item, std::size_t stride) = 0;

    // Ends the stream; the layer's bytes are then stored() (empty if nothing changed).
    void finish() { encoder_.done(); }
    std::span<const std::uint8_t> stored() const {
        return changed_ ? std::span<const std::uint8_t>(bytes_) : std::span<const std::uint8_t>();
    }

protected:
    ArithmeticEncoder encoder_;
    bool changed_ = false;  // whether the field changed at some point (else the layer is empty)

private:
    std::vector<std::uint8_t> bytes_;
};

// What an item's encoder factory needs to know about the chunk.
struct ItemEncodeSetup {
    const std::uint8_t* first = nullptr;  // the item in the chunk's first (raw) record
    std::uint32_t first_channel = 0;      // scanner channel of the first point
};

// Leaves `now` in `last` and says whether it differs from the value it replaces: whether a
// point changes the layer, for most codecs.
template <class Value>
bool replace_last(Value& last, const Value& now) {
    const bool changed = now != last;
    last = now;
    return changed;
}

// A layer encoder made from a codec, which provides
//   using Models = ...; using Value = ...;      (as for the decoders' ContextLayer)
//   Value read(const std::uint8_t* item) const;  the value in a raw item
//   bool encode(ArithmeticEncoder&, Models&, Value& last, const Value& now, const PointTrace&) const;
//       codes `now` after `last`, leaves `now` in `last`, and says whether the layer counts
//       as changed by this point (LASzip's rule for the item).
template <class Codec>
class ContextLayerEncoder final : public LayerEncoder {
public:
    ContextLayerEncoder(const ItemEncodeSetup& setup, Codec codec, ContextRule rule)
        : codec_(std::move(codec)), point14_(rule == ContextRule::kPoint14) {
        contexts_.start(setup.first_channel, codec_.read(setup.first), rule != ContextRule::kItemV3);
    }

    [[gnu::flatten]] void encode(const PointTrace* trace, std::size_t count, const std::uint8_t* item,
                                 std::size_t stride) override {
        bool changed = false;
        for (std::size_t i = 0; i < count; ++i, item += stride) {
            contexts_.select(point14_ ? trace[i].channel : trace[i].item_context);
            changed |= codec_.encode(encoder_, contexts_.models(), contexts_.value(), codec_.read(item), trace[i]);
        }
        changed_ = changed_ || changed;
    }

private:
    Codec codec_;
    ChannelContexts<typename Codec::Models, typename Codec::Value> contexts_;
    bool point14_;
};

template <class Codec>
std::unique_ptr<LayerEncoder> make_layer_encoder(const ItemEncodeSetup& setup, Codec codec, ContextRule rule) {
    return std::make_unique<ContextLayerEncoder<Codec>>(setup, std::move(codec), rule);
}

}  // namespace lidarscout::laz::detail::point14
