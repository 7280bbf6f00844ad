// A bounded on-disk cache of fetched byte ranges, so that a second look at a remote dataset
// is read from local disk. An entry is the answer to one range request of one version of a
// file: its key is the SHA-256 of the URL, the validator (ETag or Last-Modified) the answer
// carried, and the ranges. Only requests with a pinned validator are cached, so a file that
// changed on the server (a new validator, seen on the first request of a session, which is
// never served from here) never answers from an old entry. Entries are written under a
// temporary name and renamed; when the total passes the limit the least recently used
// entries are removed. The folder defaults to $XDG_CACHE_HOME/lidarscout/http (or
// ~/.cache/lidarscout/http); a limit of 0 turns the cache off.
//
// Every stored range carries its SHA-256, written with the entry and checked on every read;
// an entry's size is checked (fstat) before anything is read, against what its request can
// hold. An entry that fails (damaged on disk, replaced, truncated, of another version) is
// removed and fetched again, with a diagnostic naming it (take_diagnostics()).
//
// Entries are written by a thread of the cache's own (store() copies the reply and returns): the network's
// thread never waits on the disk, whose page cache may take a country's 250 MB catalog slower than loopback
// brings it; large ones go around the page cache (O_DIRECT) where the folder's file system allows. What is queued
// is found as if written (looked up by its path, not searched for); a reply that would make the queue pass
// kMaxQueuedBytes is not stored (a disk that cannot keep up costs a later look requests, never this one time).
#pragma once

#include <condition_variable>
#include <cstdint>
#include <cstdlib>
#include <deque>
#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <unordered_map>
#include <vector>

#include "core/diagnostic.hpp"
#include "net/http_client.hpp"

namespace lidarscout::net {

struct RangeCacheSettings {
    std::filesystem::path folder;              // empty: the default folder
    std::uint64_t max_bytes = 2ull << 30;      // 2 GiB; 0: off
};

std::filesystem::path default_cache_folder();

class RangeCache {
public:
    static constexpr std::uint64_t kMaxQueuedBytes = 32ull << 20;  // replies copied, waiting to be written
    static constexpr std::size_t kStagingBytes = 1u << 20;           // written at a time
    static constexpr std::size_t kDirectAlignment = 4096;            // of O_DIRECT's buffers, lengths and offsets
    // Entries from this size on go around the page cache; smaller ones through it (each O_DIRECT write waits on the
    // disk: a catalog's 45,000 small replies fell behind, the queue thousands long).
    static constexpr std::uint64_t kDirectMinBytes = 1u << 20;

    explicit RangeCache(RangeCacheSettings settings);
    ~RangeCache();  // (what is queued is written first)
    RangeCache(const RangeCache&) = delete;
    RangeCache& operator=(const RangeCache&) = delete;

    // The process's cache (used by remote files), set up by configure() or with defaults.
    static RangeCache& shared();
    static void configure(const RangeCacheSettings& settings);

    bool enabled() const { return settings_.max_bytes > 0; }
    std::uint64_t max_bytes() const { return settings_.max_bytes; }  // its bound (--cache-size)
    // The parts stored for `request`, or nothing.
    std::optional<std::vector<std::vector<std::uint8_t>>> find(const RangeRequest& request);
    // Queues a successful reply (for a request with a validator) to be stored, and returns.
    void store(const RangeRequest& request, const RangeReply& reply);
    // Waits until every reply queued is written (or could not be).
    void flush();

    std::uint64_t hits() const;
    // What was noticed since the last call (entries dropped), for the CLI edge to show.
    Diagnostics take_diagnostics();

private:
    using Parts = std::vector<std::vector<std::uint8_t>>;
    struct Queued {
        std::filesystem::path path;  // entry_path of its request
        Parts parts;
        std::uint64_t bytes = 0;
    };

    std::filesystem::path entry_path(const RangeRequest& request) const;
    void write(const Queued& entry);
    void write_queued();  // the writer thread
    void evict_if_needed();
    void scan_total();
    void drop(const std::filesystem::path& path, const RangeRequest& request, const std::string& why);

    RangeCacheSettings settings_;
    mutable std::mutex mutex_;
    bool scanned_ = false;
    std::uint64_t total_ = 0;
    std::uint64_t hits_ = 0;
    Diagnostics diagnostics_;
    std::deque<Queued> queue_;  // its front is being written (taken off once it is)
    std::unordered_map<std::string, const Queued*> queued_paths_;  // entry path -> its latest entry in queue_
    std::uint64_t queued_bytes_ = 0;
    bool stopping_ = false;
    std::condition_variable queued_, written_;
    std::thread writer_;  // started by the first store
    // The writer's: its staging buffer (kDirectAlignment-aligned), and whether entries go around the page cache.
    std::unique_ptr<std::uint8_t[], decltype(&std::free)> staging_{nullptr, &std::free};
    bool direct_writes_ = true;
};

}  // namespace lidarscout::net
