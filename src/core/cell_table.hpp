// Grid cells and tables of values by cell. A country's overview has hundreds of thousands of cells
// (640 m patches): a node map (std::unordered_map) allocates each one, chases a pointer on each
// lookup and holds 40 bytes a cell beside its value; building and filling those tables was most of
// what a 152,100-tile catalog's chunk points cost once read. CellTable keeps the values in the order
// they were added, in chunks that never move (a reference to a value stays good however many cells
// are added after it), the keys beside them, and finds a cell through an open-addressing index of
// 32-bit slots (linear probing, at most half full): no allocation per cell, about 16 bytes a cell
// beside its value. Cells are never removed.
#pragma once

#include <algorithm>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <utility>
#include <vector>

#include "core/radix_sort.hpp"
#include "core/random.hpp"

namespace lidarscout {

struct CellKey {
    std::int32_t ix = 0, iy = 0;
    bool operator==(const CellKey&) const = default;
    auto operator<=>(const CellKey&) const = default;
};

struct CellKeyHash {
    std::size_t operator()(const CellKey& key) const noexcept {
        const auto packed = (static_cast<std::uint64_t>(static_cast<std::uint32_t>(key.ix)) << 32) |
                            static_cast<std::uint32_t>(key.iy);
        return static_cast<std::size_t>(mix64(packed));
    }
};

// A 64-bit key that orders cells as their operator< does (ix, then iy): for radix sorts.
inline std::uint64_t cell_order(CellKey c) {
    const auto biased = [](std::int32_t v) {
        return static_cast<std::uint64_t>(static_cast<std::uint32_t>(v) ^ 0x80000000u);  // (negatives first)
    };
    return biased(c.ix) << 32 | biased(c.iy);
}

// Sorts cells as their operator< orders them, by radix: a country's candidate cells (millions, gathered tile
// by tile) in a fraction of std::sort's time.
inline void sort_cells(std::vector<CellKey>& cells) { radix_sort(cells, cell_order, 64); }

template <class T>
class CellTable {
public:
    // The chunks' sizes: 16 values, doubling to kChunk, then kChunk each (a small table stays small).
    static constexpr std::size_t kFirstChunk = 16, kChunk = 1024;

    std::size_t size() const { return keys_.size(); }
    bool empty() const { return keys_.empty(); }

    // The value of `key`; null when the table has none.
    T* find(CellKey key) {
        const std::size_t i = index_or_none(key);
        return i == kNone ? nullptr : &value(i);
    }
    const T* find(CellKey key) const {
        const std::size_t i = index_or_none(key);
        return i == kNone ? nullptr : &value(i);
    }
    T& at(CellKey key) {
        if (T* v = find(key)) return *v;
        throw std::out_of_range("cell table: no such cell");
    }
    const T& at(CellKey key) const {
        if (const T* v = find(key)) return *v;
        throw std::out_of_range("cell table: no such cell");
    }

    // The value of `key`, made (T{}) and added when the table has none (then true).
    std::pair<T*, bool> try_emplace(CellKey key) {
        if (2 * (keys_.size() + 1) > slots_.size()) rehash(std::max<std::size_t>(64, 2 * slots_.size()));
        std::size_t s = CellKeyHash{}(key) & (slots_.size() - 1);
        for (; slots_[s] != 0; s = (s + 1) & (slots_.size() - 1)) {
            if (keys_[slots_[s] - 1] == key) return {&value(slots_[s] - 1), false};
        }
        const std::size_t i = keys_.size();
        if (i >= kMaxCells) throw std::length_error("cell table: more than 4 billion cells");
        if (i == capacity()) add_chunk();
        keys_.push_back(key);
        slots_[s] = static_cast<std::uint32_t>(i + 1);
        return {&value(i), true};
    }
    T& operator[](CellKey key) { return *try_emplace(key).first; }

    // Room for `n` cells without growing the index or the keys.
    void reserve(std::size_t n) {
        keys_.reserve(n);
        if (2 * n > slots_.size()) rehash(std::bit_ceil(std::max<std::size_t>(64, 2 * n)));
    }

    // The i-th cell added, and its value (i < size()).
    CellKey key(std::size_t i) const { return keys_[i]; }
    T& value(std::size_t i) {
        const auto [chunk, at] = place(i);
        return chunks_[chunk][at];
    }
    const T& value(std::size_t i) const {
        const auto [chunk, at] = place(i);
        return chunks_[chunk][at];
    }

    // Heap bytes held: the keys, the values' chunks (whole), the index.
    std::size_t memory_bytes() const {
        return keys_.capacity() * sizeof(CellKey) + capacity() * sizeof(T) + chunks_.capacity() * sizeof(void*) +
               slots_.capacity() * sizeof(std::uint32_t);
    }
    // Bytes a cell costs beside its value, on average, with the index between a quarter and a half full.
    static constexpr std::size_t kBytesPerCell = sizeof(CellKey) + 3 * sizeof(std::uint32_t);

private:
    static constexpr std::size_t kNone = ~std::size_t{0};
    static constexpr std::size_t kMaxCells = 0xFFFFFFFEu;
    // The values held before the chunks of kChunk: 16 + 32 + ... + kChunk / 2.
    static constexpr std::size_t kGrowing = kChunk - kFirstChunk;
    static constexpr std::size_t kGrowingChunks = std::bit_width(kChunk / kFirstChunk) - 1;

    std::size_t index_or_none(CellKey key) const {
        if (slots_.empty()) return kNone;
        for (std::size_t s = CellKeyHash{}(key) & (slots_.size() - 1); slots_[s] != 0;
             s = (s + 1) & (slots_.size() - 1)) {
            if (keys_[slots_[s] - 1] == key) return slots_[s] - 1;
        }
        return kNone;
    }

    // The chunk holding value i, and where in it.
    static std::pair<std::size_t, std::size_t> place(std::size_t i) {
        if (i < kGrowing) {  // chunk k holds kFirstChunk << k, from kFirstChunk * (2^k - 1)
            const std::size_t k = std::bit_width(i / kFirstChunk + 1) - 1;
            return {k, i - kFirstChunk * ((std::size_t{1} << k) - 1)};
        }
        return {kGrowingChunks + (i - kGrowing) / kChunk, (i - kGrowing) % kChunk};
    }
    static std::size_t chunk_size(std::size_t k) { return k < kGrowingChunks ? kFirstChunk << k : kChunk; }
    std::size_t capacity() const {
        const std::size_t n = chunks_.size();
        if (n <= kGrowingChunks) return kFirstChunk * ((std::size_t{1} << n) - 1);
        return kGrowing + (n - kGrowingChunks) * kChunk;
    }
    void add_chunk() { chunks_.push_back(std::make_unique<T[]>(chunk_size(chunks_.size()))); }

    void rehash(std::size_t slots) {
        std::vector<std::uint32_t>(slots, 0).swap(slots_);
        for (std::size_t i = 0; i < keys_.size(); ++i) {
            std::size_t s = CellKeyHash{}(keys_[i]) & (slots - 1);
            while (slots_[s] != 0) s = (s + 1) & (slots - 1);
            slots_[s] = static_cast<std::uint32_t>(i + 1);
        }
    }

    std::vector<CellKey> keys_;
    std::vector<std::unique_ptr<T[]>> chunks_;
    std::vector<std::uint32_t> slots_;  // 0: empty; else the index of a key and value, plus one
};

}  // namespace lidarscout
