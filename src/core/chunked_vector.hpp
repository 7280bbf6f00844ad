// A vector kept in chunks of a fixed number of items: appending never moves the items already held
// (no copy of all of them, no fresh pages for each doubling) and wastes at most one chunk, where a
// std::vector holds up to twice its items while it grows. For the points a DEM block gathers until
// it is finished (hundreds of MB in one block of a coarse DEM).
#pragma once

#include <cstddef>
#include <vector>

namespace lidarscout {

template <class T, std::size_t kChunkItems = std::size_t{1} << 16>
class ChunkedVector {
public:
    void push_back(const T& item) {
        if (chunks_.empty() || chunks_.back().size() == kChunkItems) {
            chunks_.emplace_back();
            if (chunks_.size() > 1) chunks_.back().reserve(kChunkItems);  // the first grows as it fills
        }
        chunks_.back().push_back(item);
        ++size_;
    }

    std::size_t size() const { return size_; }
    bool empty() const { return size_ == 0; }
    T& operator[](std::size_t i) { return chunks_[i / kChunkItems][i % kChunkItems]; }
    const T& operator[](std::size_t i) const { return chunks_[i / kChunkItems][i % kChunkItems]; }

    // Keeps the first `n` items (n <= size()), freeing the chunks beyond them.
    void truncate(std::size_t n) {
        if (n >= size_) return;
        const std::size_t chunks = (n + kChunkItems - 1) / kChunkItems;
        chunks_.resize(chunks);
        if (chunks > 0) chunks_.back().resize(n - (chunks - 1) * kChunkItems);
        size_ = n;
    }

    // Frees every item.
    void clear() { std::vector<std::vector<T>>().swap(chunks_), size_ = 0; }

private:
    std::vector<std::vector<T>> chunks_;
    std::size_t size_ = 0;
};

}  // namespace lidarscout
