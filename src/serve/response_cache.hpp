// The server's one cache, shared by every client: encoded responses (gzip'd bodies with their
// ETag) by key, least recently used dropped first to stay within a byte budget. A key that
// several clients ask for at once is encoded once: the others wait for it.
#pragma once

#include <cstdint>
#include <condition_variable>
#include <functional>
#include <list>
#include <memory>
#include <mutex>
#include <string>
#include <unordered_map>

namespace lidarscout::serve {

struct Encoded {
    std::string gzipped;  // the body, gzip'd
    std::string etag;     // quoted, strong: a hash of the uncompressed body
    std::uint64_t raw_bytes = 0;
    std::uint64_t items = 0;  // points (or texels) it holds: for the bytes-per-point figures
};
using EncodedPtr = std::shared_ptr<const Encoded>;

// The strong ETag of a body: "\"<16 hex digits>\"" (FNV-1a 64 of the bytes).
std::string etag_of(const std::string& body);
// Body gzip'd with its ETag.
EncodedPtr encode(const std::string& body, std::uint64_t items);

class ResponseCache {
public:
    explicit ResponseCache(std::uint64_t budget_bytes) : budget_(budget_bytes) {}

    // The entry for `key`, made by `make` when absent (outside the lock; a concurrent caller of the
    // same key waits for it). What `make` throws reaches every waiting caller's own call of make.
    EncodedPtr get(const std::string& key, const std::function<EncodedPtr()>& make);

    // Stores `value` for `key` (replacing any), as a make of get would.
    void put(const std::string& key, EncodedPtr value);

    void set_budget(std::uint64_t bytes);
    std::uint64_t budget() const;
    std::uint64_t bytes() const;
    std::uint64_t hits() const;
    std::uint64_t misses() const;

private:
    struct Entry {
        EncodedPtr value;
        std::list<std::string>::iterator lru;
    };
    void insert(const std::string& key, EncodedPtr value);
    void evict();

    mutable std::mutex mutex_;
    std::condition_variable made_;
    std::unordered_map<std::string, Entry> entries_;
    std::unordered_map<std::string, int> making_;  // keys being made, with their waiters
    std::list<std::string> lru_;                   // most recent first
    std::uint64_t budget_, bytes_ = 0, hits_ = 0, misses_ = 0;
};

}  // namespace lidarscout::serve
