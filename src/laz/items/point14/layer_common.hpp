// Building blocks shared by the item decoders of layered LAZ chunks (compressor 3, LAS 1.4
// point formats 6-10). In such a chunk every field group has its own arithmetic-coded
// stream (a "layer"), so each layer is decoded by its own pass over a block of points:
// the POINT14 returns/XY(/Z) pass goes first and leaves a PointTrace per point (scanner
// channel, which attributes changed, return contexts) that the other layers read.
//
// Every item keeps one coding context per scanner channel (0-3). A channel's context comes
// into existence, with fresh models and the last value of the context in use, the first
// time the channel appears in the chunk. ChannelContexts does this bookkeeping, and
// ContextLayer turns a small "codec" (models, last value, how one point is decoded and
// stored) into a layer pass.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <utility>

#include "laz/arithmetic_decoder.hpp"
#include "laz/arithmetic_models.hpp"
#include "laz/items/item_common.hpp"

namespace lidarscout::laz::detail::point14 {


// What the returns/XY/Z pass learnt about one point, for the layers decoded after it.
// POINT14 version 4 hands its channel to the other items as their context. Version 3 does
// so only at a point where the channel changes and hands them context 0 at every other
// point (the reference reader resets the shared context per point); files written by it
// depend on this, so it is reproduced.
struct PointTrace {
    static constexpr std::uint8_t kScanAngleChanged = 1u << 0;
    static constexpr std::uint8_t kGpsTimeChanged = 1u << 1;
    static constexpr std::uint8_t kPointSourceChanged = 1u << 2;

    std::uint8_t channel;      // scanner channel: the context of POINT14's own layers (0-3)
    std::uint8_t item_context; // the context POINT14 hands to the other items (see above)
    std::uint8_t changed;      // k...Changed bits
    std::uint8_t return_kind;  // 2 * first return + last return (3: single return)

    bool gps_time_changed() const { return (changed & kGpsTimeChanged) != 0; }
};

// The decoder of one layer (or a constant stand-in for a layer that is empty in the chunk).
// `item` pointers address the item's bytes inside a point record; consecutive points'
// records are `stride` bytes apart.
class LayerDecoder {
public:
    virtual ~LayerDecoder() = default;
    // Writes the layer's fields of the chunk's first point (the raw point).
    virtual void write_first(std::uint8_t* item) = 0;
    // Decodes the next `count` points; trace[i] and item + i * stride belong to point i.
    virtual void decode(const PointTrace* trace, std::size_t count, std::uint8_t* item, std::size_t stride) = 0;
    // Bytes taken from the layer's stream, and bytes made up past its end (0 for a valid
    // stream). Both 0 when nothing is entropy-decoded.
    virtual std::size_t bytes_consumed() const { return 0; }
    virtual std::size_t overrun() const { return 0; }
    virtual bool entropy_coded() const { return false; }
};

// A layer decoder and where its item lies in the record.
struct PlacedLayer {
    std::unique_ptr<LayerDecoder> decoder;
    std::size_t item_offset = 0;
    const char* name = "";  // for error messages ("Z", "RGB", ...)
};

// What an item's layer factory needs to know about the chunk.
struct ItemSetup {
    const std::uint8_t* first = nullptr;                     // the item in the raw first point
    std::size_t offset = 0;                                  // the item's offset in a record
    std::span<const std::span<const std::uint8_t>> layers;   // the item's layer streams, in order
    std::uint32_t fields = 0;                                // fields:: mask the caller asked for
    std::uint32_t first_channel = 0;                         // scanner channel of the first point
    std::uint16_t version = 3;                               // item version (2 is read as 3)
};

// An array of N symbol models over `symbols` symbols, all in the start state.
template <std::size_t N>
std::array<SymbolModel, N> symbol_models(std::uint32_t symbols) {
    return [symbols]<std::size_t... I>(std::index_sequence<I...>) {
        return std::array<SymbolModel, N>{((void)I, SymbolModel(symbols))...};
    }(std::make_index_sequence<N>{});
}

// N symbol models selected by a small previous value; each is created (in the start state)
// the first time its slot is used in the chunk, so rarely used slots cost nothing.
template <std::size_t N, std::uint32_t Symbols>
class LazySymbolModels {
public:
    SymbolModel& operator[](std::size_t slot) {
        auto& m = models_[slot];
        if (!m) [[unlikely]] m.emplace(Symbols);
        return *m;
    }

private:
    std::array<std::optional<SymbolModel>, N> models_;
};

// How a layer picks the context of a point.
enum class ContextRule {
    kPoint14,  // POINT14's own layers: the point's scanner channel
    kItemV3,   // other items, version 3: POINT14's hand-on context, with the quirk below
    kItemV4,   // other items, version 4: POINT14's hand-on context
};

// The rule of a non-POINT14 item of this version (2 is read as 3).
inline ContextRule item_rule(std::uint16_t version) {
    return version >= 4 ? ContextRule::kItemV4 : ContextRule::kItemV3;
}

// The per-context state of one layer: Models (everything a context owns, including any
// running state; created on first use and then given begin(last value)) and the last
// Value. Normally a point is predicted from its own context's last value. Version 3 of
// RGB14, RGBNIR14, BYTE14 and WAVEPACKET14 has a quirk that must be reproduced: at a point
// that moves to a context already used in the chunk, the prediction (and the update) still
// uses the previous context's value.
template <class Models, class Value>
class ChannelContexts {
public:
    // Starts a chunk in context `channel` with the first point's value; `follow`: whether
    // a point always takes its own context's value (false: the version 3 quirk).
    void start(std::uint32_t channel, const Value& first, bool follow) {
        follow_ = follow;
        current_ = value_slot_ = channel;
        values_[channel] = first;
        for (auto& m : models_) m.reset();
        models_[channel] = std::make_unique<Models>();
        models_[channel]->begin(values_[channel]);
    }

    // Makes context `channel` current for the next point.
    void select(std::uint32_t channel) {
        value_slot_ = current_;
        if (channel != current_) [[unlikely]] switch_to(channel);
    }

    std::uint32_t channel() const { return current_; }
    Models& models() { return *models_[current_]; }
    Value& value() { return values_[value_slot_]; }

private:
    void switch_to(std::uint32_t channel) {
        const std::uint32_t previous = current_;
        current_ = channel;
        if (!models_[channel]) {
            values_[channel] = values_[previous];
            models_[channel] = std::make_unique<Models>();
            models_[channel]->begin(values_[channel]);
            value_slot_ = channel;
        } else if (follow_) {
            value_slot_ = channel;
        }
    }

    // unique_ptr rather than optional: Models are often nested in the class that holds
    // this, where clang cannot yet see them as default-constructible.
    std::array<std::unique_ptr<Models>, 4> models_;
    std::array<Value, 4> values_{};
    std::uint32_t current_ = 0;
    std::uint32_t value_slot_ = 0;
    bool follow_ = true;
};

// A layer pass made from a codec, which provides
//   using Models = ...; using Value = ...;          (Models: default-constructible, begin(Value&))
//   Value read(const std::uint8_t* item) const;      the value in a raw item
//   void write(std::uint8_t* item, const Value&) const;
//   void decode(ArithmeticDecoder&, Models&, Value&, const PointTrace&) const;
template <class Codec>
class ContextLayer final : public LayerDecoder {
public:
    ContextLayer(std::span<const std::uint8_t> stream, const ItemSetup& setup, Codec codec, ContextRule rule)
        : codec_(std::move(codec)), decoder_(stream), point14_(rule == ContextRule::kPoint14) {
        contexts_.start(setup.first_channel, codec_.read(setup.first), rule != ContextRule::kItemV3);
    }

    void write_first(std::uint8_t* item) override { codec_.write(item, contexts_.value()); }

    [[gnu::flatten]] void decode(const PointTrace* trace, std::size_t count, std::uint8_t* item,
                                 std::size_t stride) override {
        ArithmeticDecoder dec = decoder_;  // a local copy the compiler can keep in registers
        for (std::size_t i = 0; i < count; ++i, item += stride) {
            contexts_.select(point14_ ? trace[i].channel : trace[i].item_context);
            auto& value = contexts_.value();
            codec_.decode(dec, contexts_.models(), value, trace[i]);
            codec_.write(item, value);
        }
        decoder_ = dec;
    }

    std::size_t bytes_consumed() const override { return decoder_.bytes_consumed(); }
    std::size_t overrun() const override { return decoder_.overrun(); }
    bool entropy_coded() const override { return true; }

private:
    Codec codec_;
    ArithmeticDecoder decoder_;
    ChannelContexts<typename Codec::Models, typename Codec::Value> contexts_;
    bool point14_;
};

// Stands in for a layer that is empty in the chunk: its field never changes there, so every
// point repeats the first point's value.
template <class Codec>
class ConstantLayer final : public LayerDecoder {
public:
    ConstantLayer(const ItemSetup& setup, Codec codec) : codec_(std::move(codec)), value_(codec_.read(setup.first)) {}

    void write_first(std::uint8_t* item) override { codec_.write(item, value_); }

    void decode(const PointTrace*, std::size_t count, std::uint8_t* item, std::size_t stride) override {
        for (std::size_t i = 0; i < count; ++i, item += stride) codec_.write(item, value_);
    }

private:
    Codec codec_;
    typename Codec::Value value_;
};

// The pass for one layer: decoding when the chunk has bytes for it, else constant.
template <class Codec>
PlacedLayer make_layer(std::span<const std::uint8_t> stream, const ItemSetup& setup, Codec codec, ContextRule rule,
                       const char* name) {
    PlacedLayer placed;
    placed.item_offset = setup.offset;
    placed.name = name;
    if (stream.empty()) {
        placed.decoder = std::make_unique<ConstantLayer<Codec>>(setup, std::move(codec));
    } else {
        placed.decoder = std::make_unique<ContextLayer<Codec>>(stream, setup, std::move(codec), rule);
    }
    return placed;
}

}  // namespace lidarscout::laz::detail::point14
