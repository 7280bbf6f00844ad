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
//
// Small entries (under RangeCacheSettings::pack_below) are not files of their own: the writer appends them to a pack
// file of its process (packs/NAME.pack: each record its key, the request's SHA-256 in hex, then the entry's bytes
// as an entry file holds them) and each record's key, offset and length to the pack's index (NAME.index), read
// when the cache is first used. A country's first open had made 45,000 files of a few kilobytes, and the writer
// spent most of a core in the file system's inode allocation. A record is checked as an entry file is (its key
// too); a damaged one is forgotten (its bytes stay until its pack goes). A pack is evicted whole, by its last use.
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
    std::uint64_t pack_below = 64u << 10;      // entries smaller than this go into packs; 0: none
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
    // A pack takes records until it holds this much (or a sixteenth of max_bytes, so that evicting one frees little).
    static constexpr std::uint64_t kPackBytes = 64ull << 20;

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
        std::string key;             // entry_key of its request
        std::filesystem::path path;  // entry_path of its key
        Parts parts;
        std::uint64_t bytes = 0;
    };

    // Where a small entry lies: its pack (an index in packs_), the record's offset and length.
    struct PackSlot {
        std::uint32_t pack = 0;
        std::uint64_t offset = 0, length = 0;
    };
    struct Pack {
        std::filesystem::path path;  // NAME.pack (its index: NAME.index)
        int fd = -1;                 // open for reading once read from (or while written)
        bool touched = false;        // its time set by a read of this process (once)
    };

    std::string entry_key(const RangeRequest& request) const;  // the SHA-256 of URL, validator and ranges, in hex
    std::filesystem::path entry_path(const std::string& key) const;
    std::optional<Parts> find_packed(const std::string& key, const RangeRequest& request);
    void load_packs();    // under mutex_: every pack's index, once
    void write(const Queued& entry);
    bool append_to_pack(const Queued& entry, std::uint64_t& written);  // the writer's; false: not written
    bool open_pack();     // the writer's: a new pack of this process
    void forget_pack(std::uint32_t pack);  // under mutex_: evicted
    void write_queued();  // the writer thread
    void evict_if_needed();
    void scan_total();
    void drop(const std::filesystem::path& path, const RangeRequest& request, const std::string& why);
    std::nullopt_t drop_packed(const std::filesystem::path& pack, const PackSlot& slot, const std::string& key,
                               const RangeRequest& request, const std::string& why);

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
    // Packs (under mutex_): every one known, the slot of each key (the first 16 hex digits; the whole key is checked
    // in the record), the pack this process appends to (its index and size: the writer's).
    bool packs_loaded_ = false;
    std::vector<Pack> packs_;
    std::unordered_map<std::uint64_t, PackSlot> slots_;
    std::optional<std::uint32_t> writing_;
    int writing_index_fd_ = -1;
    std::uint64_t writing_size_ = 0;
};

}  // namespace lidarscout::net
