// Small building blocks shared by the point10-family item decoders (v1 and v2) and the v2
// encoders: byte arithmetic of the LAZ predictors, little-endian loads/stores of record
// fields, and the sets of 256 lazily created symbol models that code a byte given its
// previous value.
#pragma once

#include <array>
#include <bit>
#include <cstdint>
#include <cstring>
#include <memory>
#include <type_traits>

#include "laz/arithmetic_decoder.hpp"
#include "laz/arithmetic_models.hpp"

namespace lidarscout::laz::point10 {

// Records are written with plain memcpy of native integers.
static_assert(std::endian::native == std::endian::little, "point10 decoders assume a little-endian host");

// A byte sum taken modulo 256 (the predictors' "fold").
inline std::uint8_t wrap_byte(std::int32_t v) { return static_cast<std::uint8_t>(v); }

// A prediction clamped into the byte range.
inline std::int32_t clamp_byte(std::int32_t v) { return v < 0 ? 0 : (v > 255 ? 255 : v); }

template <class T>
inline T load(const std::uint8_t* p) {
    T v;
    std::memcpy(&v, p, sizeof v);
    return v;
}

template <class T>
inline void store(std::uint8_t* p, T v) {
    std::memcpy(p, &v, sizeof v);
}

// Wrapping 32-bit addition (the coded deltas wrap like two's-complement integers).
inline std::int32_t add_wrapping(std::int32_t a, std::int32_t b) {
    return static_cast<std::int32_t>(static_cast<std::uint32_t>(a) + static_cast<std::uint32_t>(b));
}

// Wrapping 32-bit multiplication.
inline std::int32_t mul_wrapping(std::int32_t a, std::int32_t b) {
    return static_cast<std::int32_t>(static_cast<std::uint32_t>(a) * static_cast<std::uint32_t>(b));
}

// One 256-symbol model per previous value of a byte field; a model comes into existence
// (in its start state) the first time its previous value occurs in a chunk.
class ByteModelsByPrevious {
public:
    // Back to the start state: every model that exists is reset.
    void reset() {
        for (auto& m : models_) {
            if (m) m->reset();
        }
    }

    // The model of the byte that follows `previous` (created on first use).
    SymbolModel& model_after(std::uint8_t previous) {
        auto& m = models_[previous];
        if (!m) [[unlikely]] create(previous);
        return *m;
    }

    // Decodes the byte that follows `previous`.
    std::uint8_t decode(ArithmeticDecoder& dec, std::uint8_t previous) {
        return static_cast<std::uint8_t>(dec.decode_symbol(model_after(previous)));
    }

private:
    void create(std::uint8_t previous) { models_[previous] = std::make_unique<SymbolModel>(256); }

    std::array<std::unique_ptr<SymbolModel>, 256> models_;
};

// An item coder (decoder or encoder) for one LAZ item: coders of variable-size items (BYTE)
// take the item size, the others are default-constructed.
template <class Item, class LazItemT>
Item make_item(const LazItemT& item) {
    if constexpr (std::is_constructible_v<Item, std::size_t>) {
        return Item(item.size);
    } else {
        return Item();
    }
}

}  // namespace lidarscout::laz::point10
