// Round trip of one point10-family item coder pair, for the per-item tests: the items are
// encoded by the item's encoder into one arithmetic-coded stream (the first item raw, as a
// chunk starts) and decoded by its decoder; the test compares what comes back.
#pragma once

#include <cstdint>
#include <cstring>
#include <random>
#include <vector>

#include "laz/arithmetic_decoder.hpp"
#include "laz/arithmetic_encoder.hpp"

namespace lidarscout::laz::test {

// `items`: n items of `size` bytes, back to back. Returns the n items as decoded.
template <class Encoder, class Decoder>
std::vector<std::uint8_t> item_round_trip(const std::vector<std::uint8_t>& items, std::size_t size,
                                          Encoder encoder, Decoder decoder) {
    const std::size_t n = items.size() / size;
    std::vector<std::uint8_t> stream;
    ArithmeticEncoder enc;
    enc.start(stream);
    encoder.init(items.data());
    for (std::size_t i = 1; i < n; ++i) encoder.encode(enc, items.data() + i * size);
    enc.done();

    std::vector<std::uint8_t> out(items.size());
    std::memcpy(out.data(), items.data(), size);
    decoder.init(items.data());
    ArithmeticDecoder dec(stream);
    for (std::size_t i = 1; i < n; ++i) decoder.decode(dec, out.data() + i * size);
    return out;
}

// A value that mostly repeats the last one (probability `keep`), else a uniform new one.
template <class T>
T sticky(std::mt19937& rng, T last, double keep, T lo, T hi) {
    if (std::uniform_real_distribution<double>(0, 1)(rng) < keep) return last;
    return static_cast<T>(std::uniform_int_distribution<long long>(lo, hi)(rng));
}

}  // namespace lidarscout::laz::test
