// ArithmeticEncoder: stream start and end, carries and output growth (see the header).
#include "laz/arithmetic_encoder.hpp"

#include <algorithm>

namespace lidarscout::laz {
namespace {

// Output grows by at least this much at a time (a chunk of points needs tens of KiB).
constexpr std::size_t kMinGrowth = 1u << 14;

}  // namespace

void ArithmeticEncoder::start(std::vector<std::uint8_t>& out) {
    out_ = &out;
    stream_begin_ = out.size();
    next_ = out.data() + out.size();
    end_ = next_;  // the first renormalisation grows the vector
    base_ = 0;
    length_ = kMaxLength;
}

void ArithmeticEncoder::grow() {
    // Growing with the stream (not with all of *out_, which may hold many earlier chunks)
    // keeps the zero-filling of new room proportional to this stream's length.
    const std::size_t used = static_cast<std::size_t>(next_ - out_->data());
    out_->resize(used + std::max(used - stream_begin_, kMinGrowth));
    next_ = out_->data() + used;
    end_ = out_->data() + out_->size();
}

void ArithmeticEncoder::propagate_carry() {
    // The interval always lies below 1.0, so a carry never runs past the stream's first byte.
    std::uint8_t* const first = out_->data() + stream_begin_;
    std::uint8_t* p = next_;
    while (p != first) {
        --p;
        if (*p != 0xFF) {
            ++*p;
            return;
        }
        *p = 0;
    }
}

void ArithmeticEncoder::done() {
    // Pick a value inside the final interval that needs as few further bytes as possible:
    // one byte when the interval is wide enough, else two; then flush.
    const bool wide = length_ > 2 * kMinLength;
    if (wide) {
        add_to_base(kMinLength);
        length_ = kMinLength >> 1;
    } else {
        add_to_base(kMinLength >> 1);
        length_ = kMinLength >> 9;
    }
    renormalize();
    // The decoder primes four bytes and reads ahead; LASzip pads so that it never reads past
    // the stream: three zero bytes after a one-byte end, two after a two-byte end.
    const std::size_t padding = wide ? 3 : 2;
    if (static_cast<std::size_t>(end_ - next_) < padding) grow();
    for (std::size_t i = 0; i < padding; ++i) *next_++ = 0;
    out_->resize(static_cast<std::size_t>(next_ - out_->data()));
    out_ = nullptr;
    next_ = end_ = nullptr;
}

}  // namespace lidarscout::laz
