// Adaptive probability models of the LASzip arithmetic coder: a binary model and a
// multi-symbol model. Their update schedules are part of the LAZ format: a decoder only
// reproduces a file's points if it adapts exactly as the writer did, so every constant and
// rounding step below follows the format, not taste. The same models serve the decoder and
// the encoder; the decoder's lookup table and guess are only accelerators.
#pragma once

#include <algorithm>
#include <cstdint>
#include <memory>

namespace lidarscout::laz {

// Interval length bits dropped before multiplying by a probability.
inline constexpr std::uint32_t kBitProbabilityBits = 13;     // binary model: p0 in 1/8192
inline constexpr std::uint32_t kSymbolProbabilityBits = 15;  // symbol model: cdf in 1/32768
// Counts are halved when their total exceeds these.
inline constexpr std::uint32_t kBitCountLimit = 1u << kBitProbabilityBits;
inline constexpr std::uint32_t kSymbolCountLimit = 1u << kSymbolProbabilityBits;
// Largest alphabet a symbol model accepts.
inline constexpr std::uint32_t kMaxSymbols = 1u << 11;

// Probability of a 0 bit, re-estimated from counts at growing intervals (4, 5, 6, ... 64).
class BitModel {
public:
    BitModel() { reset(); }
    // Back to the equiprobable start state (done at the start of every chunk).
    void reset();

    std::uint32_t zero_probability() const { return zero_probability_; }

    // Records one coded bit; re-estimates the probability when an update is due.
    void record(std::uint32_t bit) {
        if (bit == 0) ++zero_count_;
        if (--until_update_ == 0) update();
    }

private:
    void update();

    std::uint32_t zero_count_ = 0;
    std::uint32_t total_count_ = 0;
    std::uint32_t zero_probability_ = 0;
    std::uint32_t update_interval_ = 0;
    std::uint32_t until_update_ = 0;
};

// Cumulative distribution over `symbols` symbols (2 .. 2048), re-estimated from counts at
// growing intervals. Models of more than 16 symbols also keep a lookup table that maps the
// top bits of a scaled code value to a small range of candidate symbols.
class SymbolModel {
public:
    // The type of the tables' entries: 16 bits, so that more models stay in the L1 cache (a
    // 256-symbol model takes 1.5 KiB). Every entry fits: cdf values are below 2^15, lookup
    // entries are symbols (below 2^11), and a count stays below 2^15 + (2048 + 6) * 8 < 2^16
    // (the total is at most 2^15 after an update, and the next update comes within that many
    // symbols).
    using Entry = std::uint16_t;

    // Throws lidarscout::Error if `symbols` is outside 2 .. kMaxSymbols.
    explicit SymbolModel(std::uint32_t symbols);
    SymbolModel(SymbolModel&&) noexcept = default;
    SymbolModel& operator=(SymbolModel&&) noexcept = default;
    SymbolModel(const SymbolModel&) = delete;
    SymbolModel& operator=(const SymbolModel&) = delete;

    // Back to the uniform start state (done at the start of every chunk).
    void reset();

    std::uint32_t symbols() const { return symbols_; }
    std::uint32_t last_symbol() const { return symbols_ - 1; }
    // Lower end of symbol s in the cumulative distribution, scaled to 2^15 (s < symbols()), and
    // kSentinel for s == symbols() (and up to kPlainWidth in models without a lookup table).
    std::uint32_t cdf(std::uint32_t s) const { return cdf_[s]; }
    // The cdf table itself (symbols() + 1 entries, at least kPlainWidth), for searches that read
    // many entries at once (bench_lanes' vector searches).
    const Entry* cdf_table() const { return cdf_; }
    bool has_lookup() const { return lookup_ != nullptr; }
    // Lookup table (lookup_size() + 2 entries) and the shift that maps a 15-bit scaled
    // value to its index.
    const Entry* lookup() const { return lookup_; }
    std::uint32_t lookup_size() const { return lookup_size_; }
    std::uint32_t lookup_shift() const { return lookup_shift_; }
    // The last symbol s with cdf(s) * length <= value, i.e. cdf(s) <= value / length, for models
    // without a lookup table (at most 16 symbols), without dividing: a branch-free count over a
    // fixed kPlainWidth entries, as the symbol a code value falls in is hard to predict, and so is
    // a loop whose length is the alphabet's. The products are taken in 64 bits (a sentinel times
    // the decoder's length, below 2^17, exceeds 32).
    std::uint32_t last_at_or_below(std::uint32_t value, std::uint32_t length) const {
        std::uint32_t s = 0;
        for (std::uint32_t i = 1; i < kPlainWidth; ++i) s += std::uint64_t{cdf_[i]} * length <= value ? 1u : 0u;
        return std::min(s, symbols_ - 1);  // only a corrupt code value passes a sentinel
    }
    // The cdf entries past the last symbol hold kSentinel: above every valid scaled code value
    // (below 2^15 + 2^6), and kSentinel * length above every valid code value (below
    // (length + 1) * 2^15). Every model has one such entry, cdf(symbols()), so that a search may
    // look one past its candidate; models without a lookup table have them up to kPlainWidth.
    static constexpr std::uint32_t kSentinel = 0xFFFF;
    static constexpr std::uint32_t kPlainWidth = 16;

    // The symbol ArithmeticDecoder::decode_likely_symbol tries first, without searching: the most
    // frequent one at the last re-estimation, when its count is at least half the total (else an
    // empty interval, which no code value falls in). Its interval [low, high) in cdf units; `last`:
    // it is the last symbol, whose interval runs to the end of the decoder's length (high unused).
    struct Guess {
        Entry symbol = 0;
        Entry low = 0;
        Entry high = 0;
        bool last = false;
    };
    const Guess& guess() const { return guess_; }

    // Records one coded symbol; re-estimates the distribution when an update is due.
    void record(std::uint32_t s) {
        ++counts_[s];
        if (--until_update_ == 0) update();
    }

private:
    static const SymbolModel* start_state(std::uint32_t symbols);
    void update();
    void fill_lookup();
    void choose_guess(std::uint32_t most_frequent, std::uint32_t count);  // count: most_frequent's

    std::uint32_t symbols_ = 0;
    std::size_t entries_ = 0;           // of storage_
    std::unique_ptr<Entry[]> storage_;  // cdf, counts, lookup table in one block
    Entry* cdf_ = nullptr;
    Entry* counts_ = nullptr;
    Entry* lookup_ = nullptr;
    std::uint32_t lookup_size_ = 0;
    std::uint32_t lookup_shift_ = 0;
    std::uint32_t total_count_ = 0;
    std::uint32_t update_interval_ = 0;
    std::uint32_t until_update_ = 0;
    Guess guess_;
};

}  // namespace lidarscout::laz
