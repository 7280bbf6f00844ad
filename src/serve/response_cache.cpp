// The shared LRU cache of encoded responses.
#include "serve/response_cache.hpp"

#include <fmt/format.h>

#include "serve/gzip.hpp"

namespace lidarscout::serve {
namespace {

constexpr std::uint64_t kEntryOverhead = 128;  // key, node and bookkeeping per entry (estimate)

std::uint64_t entry_bytes(const std::string& key, const Encoded& e) {
    return key.size() + e.gzipped.size() + e.etag.size() + kEntryOverhead;
}

}  // namespace

std::string etag_of(const std::string& body) {
    std::uint64_t h = 14695981039346656037ull;
    for (const unsigned char c : body) h = (h ^ c) * 1099511628211ull;
    return fmt::format("\"{:016x}\"", h);
}

EncodedPtr encode(const std::string& body, std::uint64_t items) {
    auto e = std::make_shared<Encoded>();
    e->gzipped = gzip(body);
    e->etag = etag_of(body);
    e->raw_bytes = body.size();
    e->items = items;
    return e;
}

EncodedPtr ResponseCache::get(const std::string& key, const std::function<EncodedPtr()>& make) {
    std::unique_lock lock(mutex_);
    made_.wait(lock, [&] { return !making_.contains(key); });
    if (auto it = entries_.find(key); it != entries_.end()) {
        lru_.splice(lru_.begin(), lru_, it->second.lru);
        ++hits_;
        return it->second.value;
    }
    ++misses_;
    making_[key] = 1;
    lock.unlock();
    EncodedPtr value;
    try {
        value = make();
    } catch (...) {
        lock.lock();
        making_.erase(key);
        made_.notify_all();
        throw;
    }
    lock.lock();
    making_.erase(key);
    insert(key, value);
    made_.notify_all();
    return value;
}

void ResponseCache::put(const std::string& key, EncodedPtr value) {
    std::lock_guard lock(mutex_);
    insert(key, std::move(value));
}

void ResponseCache::insert(const std::string& key, EncodedPtr value) {
    if (auto it = entries_.find(key); it != entries_.end()) {  // replaced
        bytes_ -= entry_bytes(it->first, *it->second.value);
        lru_.erase(it->second.lru);
        entries_.erase(it);
    }
    lru_.push_front(key);
    bytes_ += entry_bytes(key, *value);
    entries_[key] = Entry{std::move(value), lru_.begin()};
    evict();
}

void ResponseCache::evict() {
    while (bytes_ > budget_ && !lru_.empty()) {
        const auto it = entries_.find(lru_.back());
        bytes_ -= entry_bytes(it->first, *it->second.value);
        entries_.erase(it);
        lru_.pop_back();
    }
}

void ResponseCache::set_budget(std::uint64_t bytes) {
    std::lock_guard lock(mutex_);
    budget_ = bytes;
    evict();
}

std::uint64_t ResponseCache::budget() const {
    std::lock_guard lock(mutex_);
    return budget_;
}

std::uint64_t ResponseCache::bytes() const {
    std::lock_guard lock(mutex_);
    return bytes_;
}

std::uint64_t ResponseCache::hits() const {
    std::lock_guard lock(mutex_);
    return hits_;
}

std::uint64_t ResponseCache::misses() const {
    std::lock_guard lock(mutex_);
    return misses_;
}

}  // namespace lidarscout::serve
