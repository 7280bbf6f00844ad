// Small building blocks shared by the item coders of both families (point10 items of
// point-wise chunks, point14 items of layered chunks): byte arithmetic of the LAZ predictors,
// little-endian loads/stores of record fields, the sets of 256 lazily created symbol models
// that code a byte given its previous value, the running median of the X/Y deltas, and the
// GPS time delta helpers of the two GPS time encoders.
#pragma once

#include <array>
#include <bit>
#include <cstdint>
#include <cstring>
#include <limits>
#include <memory>
#include <optional>
#include <type_traits>

#include "laz/arithmetic_decoder.hpp"
#include "laz/arithmetic_models.hpp"

namespace lidarscout::laz::detail {

// Records are written with plain memcpy of native integers.
static_assert(std::endian::native == std::endian::little, "the item coders assume a little-endian host");

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

// Median of the last five values, updated in the LAZ way: the window is a sorted list of
// five, and each new value evicts the largest or the smallest, alternating whenever the
// new value lands on the side being evicted from.
class RunningMedian5 {
public:
    void reset() {
        sorted_ = {};
        evict_largest_ = true;
    }
    std::int32_t median() const { return sorted_[2]; }

    void add(std::int32_t v) {
        if (evict_largest_) {
            const bool upper = v >= sorted_[2];
            int i = 4;
            for (; i > 0 && v < sorted_[i - 1]; --i) sorted_[i] = sorted_[i - 1];
            sorted_[i] = v;
            if (upper) evict_largest_ = false;
        } else {
            const bool lower = v <= sorted_[2];
            int i = 0;
            for (; i < 4 && sorted_[i + 1] < v; ++i) sorted_[i] = sorted_[i + 1];
            sorted_[i] = v;
            if (lower) evict_largest_ = true;
        }
    }

private:
    std::array<std::int32_t, 5> sorted_{};
    bool evict_largest_ = true;
};

// A difference of two times (bit patterns) as an int32, if it fits: a delta that can be coded.
inline std::optional<std::int32_t> gps_delta_as_int32(std::uint64_t difference) {
    const auto d = static_cast<std::int64_t>(difference);
    if (d < std::numeric_limits<std::int32_t>::min() || d > std::numeric_limits<std::int32_t>::max()) {
        return std::nullopt;
    }
    return static_cast<std::int32_t>(d);
}

// The multiple of `last_delta` (not 0) that `delta` is, rounded half away from zero the
// way LASzip does it: the quotient in single precision, the rounding in double, and a
// quotient outside the int32 range giving INT32_MIN (what an x86-64 build of LASzip gets
// from that conversion).
std::int32_t gps_delta_multiple(std::int32_t delta, std::int32_t last_delta);

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

}  // namespace lidarscout::laz::detail
