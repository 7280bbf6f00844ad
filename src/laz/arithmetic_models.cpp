// Start states and periodic re-estimation of the adaptive models (see the header).
#include "laz/arithmetic_models.hpp"

#include <algorithm>
#include <memory>
#include <string>
#include <vector>

#include "core/error.hpp"

namespace lidarscout::laz {
namespace {

// 2^31 / total: probabilities are computed in 31-bit fixed point, then shifted down.
constexpr std::uint32_t kFixedPointOne = 0x80000000u;
constexpr std::uint32_t kSmallestLookupBits = 3;
// Larger alphabets get a lookup table; smaller ones are searched over a fixed width.
constexpr std::uint32_t kLargestPlainAlphabet = SymbolModel::kPlainWidth;
constexpr std::uint32_t kBitMaxUpdateInterval = 64;

}  // namespace

// ---- BitModel ---------------------------------------------------------------------------

void BitModel::reset() {
    zero_count_ = 1;
    total_count_ = 2;
    zero_probability_ = 1u << (kBitProbabilityBits - 1);
    update_interval_ = 4;
    until_update_ = 4;
}

void BitModel::update() {
    total_count_ += update_interval_;
    if (total_count_ > kBitCountLimit) {
        total_count_ = (total_count_ + 1) >> 1;
        zero_count_ = (zero_count_ + 1) >> 1;
        if (zero_count_ == total_count_) ++total_count_;  // keep p(1) above zero
    }
    const std::uint32_t scale = kFixedPointOne / total_count_;
    zero_probability_ = (zero_count_ * scale) >> (31 - kBitProbabilityBits);

    update_interval_ = std::min((5 * update_interval_) >> 2, kBitMaxUpdateInterval);
    until_update_ = update_interval_;
}

// ---- SymbolModel ------------------------------------------------------------------------

SymbolModel::SymbolModel(std::uint32_t symbols) : symbols_(symbols) {
    if (symbols < 2 || symbols > kMaxSymbols) {
        throw Error("arithmetic symbol model: unsupported alphabet of " + std::to_string(symbols) +
                    " symbols (2 to " + std::to_string(kMaxSymbols) + " allowed)");
    }
    std::size_t lookup_entries = 0;
    if (symbols > kLargestPlainAlphabet) {
        std::uint32_t bits = kSmallestLookupBits;
        while (symbols > (1u << bits)) ++bits;  // about one entry per symbol: the search after the lookup rarely runs
        lookup_size_ = 1u << bits;
        lookup_shift_ = kSymbolProbabilityBits - bits;
        lookup_entries = lookup_size_ + 2;
    }
    const std::size_t cdf_entries = std::max<std::size_t>(symbols + 1, lookup_entries ? 0 : kPlainWidth);
    entries_ = cdf_entries + std::size_t{symbols} + lookup_entries;
    storage_ = std::make_unique<Entry[]>(entries_);
    cdf_ = storage_.get();
    std::fill(cdf_ + symbols, cdf_ + cdf_entries, Entry{kSentinel});
    counts_ = cdf_ + cdf_entries;
    lookup_ = lookup_entries ? counts_ + symbols : nullptr;
    reset();
}

// The start state of a model of `symbols` symbols, made once per alphabet size and thread (nullptr while it is
// being made: its own reset computes it).
const SymbolModel* SymbolModel::start_state(std::uint32_t symbols) {
    thread_local std::vector<std::unique_ptr<SymbolModel>> made;
    thread_local bool making = false;
    if (making) return nullptr;
    if (made.size() <= symbols) made.resize(symbols + 1);
    if (!made[symbols]) {
        making = true;
        try {
            made[symbols] = std::make_unique<SymbolModel>(symbols);
        } catch (...) {
            making = false;
            throw;
        }
        making = false;
    }
    return made[symbols].get();
}

// A copy of the start state where one was made (a 256-symbol model's distribution and lookup table are
// otherwise computed anew: a LAZ chunk table's coder is reset for every tile, 152,100 of them in a country).
void SymbolModel::reset() {
    if (const SymbolModel* start = start_state(symbols_)) {
        std::copy_n(start->storage_.get(), entries_, storage_.get());
        total_count_ = start->total_count_;
        update_interval_ = start->update_interval_;
        until_update_ = start->until_update_;
        guess_ = start->guess_;
        return;
    }
    std::fill(counts_, counts_ + symbols_, 1u);
    total_count_ = 0;
    update_interval_ = symbols_;
    update();
    update_interval_ = (symbols_ + 6) >> 1;  // the first re-estimation comes early
    until_update_ = update_interval_;
}

void SymbolModel::update() {
    total_count_ += update_interval_;
    if (total_count_ > kSymbolCountLimit) {
        total_count_ = 0;
        for (std::uint32_t s = 0; s < symbols_; ++s) {
            counts_[s] = (counts_[s] + 1) >> 1;
            total_count_ += counts_[s];
        }
    }

    const std::uint32_t scale = kFixedPointOne / total_count_;
    std::uint32_t sum = 0;
    std::uint32_t most_frequent = 0, largest = 0;
    if (lookup_) std::fill(lookup_, lookup_ + lookup_size_ + 2, Entry{0});
    for (std::uint32_t s = 0; s < symbols_; ++s) {
        cdf_[s] = static_cast<Entry>((scale * sum) >> (31 - kSymbolProbabilityBits));
        const std::uint32_t count = counts_[s];
        sum += count;
        if (count > largest) {
            largest = count;
            most_frequent = s;
        }
        if (lookup_) ++lookup_[(cdf_[s] >> lookup_shift_) + 1];  // how many symbols start in each slot
    }
    if (lookup_) fill_lookup();
    choose_guess(most_frequent, largest);

    update_interval_ = std::min((5 * update_interval_) >> 2, (symbols_ + 6) << 3);
    until_update_ = update_interval_;
}

// The guess after a re-estimation (see Guess). Below half the counts it would miss more often
// than it hits, and every miss costs a misprediction on top of the search.
void SymbolModel::choose_guess(std::uint32_t most_frequent, std::uint32_t count) {
    guess_ = {};
    if (count < (total_count_ >> 1)) return;
    guess_.symbol = static_cast<Entry>(most_frequent);
    guess_.low = cdf_[most_frequent];
    guess_.last = most_frequent == last_symbol();
    guess_.high = guess_.last ? Entry{0} : cdf_[most_frequent + 1];
}

// Turns the per-slot counts in lookup_[1 ..] into the table: entry j (1 .. lookup_size_ + 1) is
// the last symbol that starts in a slot below j, i.e. (the symbols starting below j) - 1, the
// first candidate for a code value in slot j - 1 ... (entry 0: symbol 0). A prefix sum, without
// the branches of filling slot ranges symbol by symbol.
void SymbolModel::fill_lookup() {
    std::uint32_t below = 0;
    for (std::uint32_t j = 1; j <= lookup_size_ + 1; ++j) {
        below += lookup_[j];
        lookup_[j] = static_cast<Entry>(below - 1);
    }
    lookup_[0] = 0;
}

}  // namespace lidarscout::laz
