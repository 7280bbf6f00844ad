// The on-disk range cache: entry files (a magic, a count, then each part's length, SHA-256 and
// bytes), written under a temporary name (around the page cache where the file system allows) and renamed by
// a thread of its own, small ones appended to packs with an index; checked when read, evicted least
// recently used first.
#include "net/range_cache.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <iterator>
#include <memory>
#include <string_view>
#include <utility>
#include <variant>

#include "core/sha256.hpp"
#include "core/thread_priority.hpp"
#include "net/url.hpp"

namespace lidarscout::net {

namespace fs = std::filesystem;

namespace {

constexpr std::uint64_t kMaxParts = 1u << 20;
constexpr std::string_view kMagic = "LSRANGE2";   // the entry format (8 bytes)
constexpr std::size_t kDigest = 64;               // a part's SHA-256, in hex
constexpr std::size_t kStagingBytes = RangeCache::kStagingBytes;
constexpr std::size_t kDirectAlignment = RangeCache::kDirectAlignment;
constexpr int kWriterNice = 10;                   // the writing thread's (write_queued)

void put_u64(std::string& out, std::uint64_t v) {
    for (int i = 0; i < 8; ++i) out.push_back(static_cast<char>(v >> (8 * i)));
}

bool get_u64(const std::string& in, std::size_t& at, std::uint64_t& v) {
    if (in.size() - at < 8) return false;
    v = 0;
    for (int i = 0; i < 8; ++i) v |= std::uint64_t{static_cast<unsigned char>(in[at + i])} << (8 * i);
    at += 8;
    return true;
}

std::string digest(const std::uint8_t* data, std::size_t n) { return sha256_hex(std::span(data, n)); }

bool write_all(int fd, const char* data, std::size_t n, std::optional<std::uint64_t> at = std::nullopt) {
    for (std::size_t done = 0; done < n;) {
        const ssize_t w = at ? ::pwrite(fd, data + done, n - done, static_cast<off_t>(*at + done))
                             : ::write(fd, data + done, n - done);
        if (w < 0 && errno == EINTR) continue;
        if (w <= 0) return false;
        done += static_cast<std::size_t>(w);
    }
    return true;
}

bool read_all(int fd, char* data, std::size_t n, std::uint64_t at) {
    for (std::size_t done = 0; done < n;) {
        const ssize_t got = ::pread(fd, data + done, n - done, static_cast<off_t>(at + done));
        if (got < 0 && errno == EINTR) continue;
        if (got <= 0) return false;
        done += static_cast<std::size_t>(got);
    }
    return true;
}

// An entry file's bytes on their way to disk, through a staging buffer of kStagingBytes written whole. Where the
// file was opened with O_DIRECT the bytes go around the page cache: a country's catalog and sidecar (360 MB on a
// first open) copied into fresh page-cache pages cost a core for over a second on a virtual machine, while the
// catalog's parse waited for it; the last block is padded to the alignment and the file cut to its size.
class EntryOutput {
public:
    EntryOutput(int fd, std::uint8_t* staging, bool direct) : fd_(fd), staging_(staging), direct_(direct) {}

    bool put(const void* data, std::size_t n) {
        for (const auto* p = static_cast<const std::uint8_t*>(data); n > 0;) {
            const std::size_t take = std::min(n, kStagingBytes - filled_);
            std::memcpy(staging_ + filled_, p, take);
            filled_ += take, p += take, n -= take;
            if (filled_ == kStagingBytes && !write_staging(kStagingBytes)) return false;
        }
        return true;
    }

    bool finish() {
        const std::uint64_t size = written_ + filled_;
        if (!direct_) return write_staging(filled_);
        const std::size_t padded = (filled_ + kDirectAlignment - 1) / kDirectAlignment * kDirectAlignment;
        std::memset(staging_ + filled_, 0, padded - filled_);
        return write_staging(padded) && ::ftruncate(fd_, static_cast<off_t>(size)) == 0;
    }

private:
    bool write_staging(std::size_t n) {
        if (!write_all(fd_, reinterpret_cast<const char*>(staging_), n)) return false;
        written_ += n, filled_ = 0;
        return true;
    }

    int fd_;
    std::uint8_t* staging_;
    bool direct_;
    std::size_t filled_ = 0;
    std::uint64_t written_ = 0;
};

// Puts the entry for `parts` (a reply's) through put(data, n) (false: it could not be): magic, part count, then
// each part's length, SHA-256 and bytes; false when it could not be.
template <typename Put>
bool put_entry(Put&& put, const std::vector<std::vector<std::uint8_t>>& parts) {
    std::string head(kMagic);
    put_u64(head, parts.size());
    for (const auto& p : parts) {
        put_u64(head, p.size());
        head += digest(p.data(), p.size());
        if (!put(head.data(), head.size()) || !put(p.data(), p.size())) return false;
        head.clear();
    }
    return put(head.data(), head.size());
}

// Writes the entry file for `parts`; false when it could not be.
bool write_entry(EntryOutput& out, const std::vector<std::vector<std::uint8_t>>& parts) {
    return put_entry([&](const void* data, std::size_t n) { return out.put(data, n); }, parts) && out.finish();
}

// A pack's record: its key (kKeyChars hex digits), then the entry.
constexpr std::size_t kKeyChars = 64;
// An index's record: a record's key, then its offset and length in the pack (u64 each).
constexpr std::size_t kIndexRecord = kKeyChars + 16;
constexpr std::string_view kPackFolder = "packs";

// The slot map's key: a key's first 16 hex digits.
std::uint64_t key_prefix(std::string_view key) {
    std::uint64_t v = 0;
    for (const char c : key.substr(0, 16)) v = v * 16 + static_cast<std::uint64_t>(c <= '9' ? c - '0' : c - 'a' + 10);
    return v;
}

// "URL, bytes A-B" or "URL, N ranges": a request in a message (its URL redacted).
std::string described(const RangeRequest& request) {
    const auto& first = request.ranges.front();
    const std::string ranges = request.ranges.size() == 1
                                   ? "bytes " + std::to_string(first.offset) + "-" + std::to_string(first.last())
                                   : std::to_string(request.ranges.size()) + " ranges";
    return redact_url(request.url) + ", " + ranges;
}

// The largest entry `request` can have (every range whole).
std::uint64_t max_entry_size(const RangeRequest& request) {
    std::uint64_t size = kMagic.size() + 8;
    for (const auto& r : request.ranges) size += 8 + kDigest + r.length;
    return size;
}

using Parts = std::vector<std::vector<std::uint8_t>>;

// The parts of an entry file's content, or why it cannot be used for `request`.
std::variant<Parts, std::string> decode(const std::string& in, const RangeRequest& request) {
    if (in.compare(0, kMagic.size(), kMagic) != 0) return std::string("not an entry of this version");
    std::size_t at = kMagic.size();
    std::uint64_t n = 0;
    if (!get_u64(in, at, n) || n != request.ranges.size() || n > kMaxParts) return std::string("wrong part count");
    Parts parts(n);
    for (std::uint64_t i = 0; i < n; ++i) {
        std::uint64_t len = 0;
        if (!get_u64(in, at, len) || len > request.ranges[i].length || in.size() - at < kDigest ||
            len > in.size() - at - kDigest) {
            return "part " + std::to_string(i) + " has an impossible length";
        }
        const std::string stored = in.substr(at, kDigest);
        at += kDigest;
        const auto* data = reinterpret_cast<const std::uint8_t*>(in.data() + at);
        if (digest(data, len) != stored) return "part " + std::to_string(i) + " does not match its SHA-256";
        parts[i].assign(data, data + len);
        at += len;
    }
    if (at != in.size()) return std::string("bytes after its last part");
    return parts;
}

// An entry file as read: absent, or its bytes, or why they were not read.
struct EntryFile {
    bool exists = false;
    std::string content;
    std::string problem;  // "" when `content` is the whole file
};

// Reads the whole entry file, only when its size (fstat) is possible for `request`.
EntryFile read_entry(const fs::path& path, const RangeRequest& request) {
    EntryFile entry;
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) return entry;
    entry.exists = true;
    struct stat st {};
    const std::uint64_t max = max_entry_size(request);
    if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        entry.problem = "not a regular file";
    } else if (static_cast<std::uint64_t>(st.st_size) > max) {
        entry.problem = "its size, " + std::to_string(st.st_size) + " bytes, is more than its ranges can hold (" +
                        std::to_string(max) + ")";
    } else {
        entry.content.resize(static_cast<std::size_t>(st.st_size));
        if (!read_all(fd, entry.content.data(), entry.content.size(), 0)) entry.problem = "it could not be read whole";
    }
    ::close(fd);
    return entry;
}

std::mutex& shared_mutex() {
    static std::mutex m;
    return m;
}

std::unique_ptr<RangeCache>& shared_slot() {
    static std::unique_ptr<RangeCache> cache;
    return cache;
}

}  // namespace

fs::path default_cache_folder() {
    const char* xdg = std::getenv("XDG_CACHE_HOME");
    if (xdg && *xdg) return fs::path(xdg) / "lidarscout" / "http";
    const char* home = std::getenv("HOME");
    return fs::path(home && *home ? home : "/tmp") / ".cache" / "lidarscout" / "http";
}

RangeCache::RangeCache(RangeCacheSettings settings) : settings_(std::move(settings)) {
    if (settings_.folder.empty()) settings_.folder = default_cache_folder();
}

RangeCache::~RangeCache() {
    {
        std::lock_guard lock(mutex_);
        stopping_ = true;
    }
    queued_.notify_all();
    if (writer_.joinable()) writer_.join();
    for (const Pack& p : packs_) {
        if (p.fd >= 0) ::close(p.fd);
    }
    if (writing_index_fd_ >= 0) ::close(writing_index_fd_);
}

RangeCache& RangeCache::shared() {
    std::lock_guard lock(shared_mutex());
    auto& slot = shared_slot();
    if (!slot) slot = std::make_unique<RangeCache>(RangeCacheSettings{});
    return *slot;
}

void RangeCache::configure(const RangeCacheSettings& settings) {
    std::lock_guard lock(shared_mutex());
    shared_slot() = std::make_unique<RangeCache>(settings);
}

std::string RangeCache::entry_key(const RangeRequest& request) const {
    const std::string key = request.url + '\n' + request.validator + '\n' + range_header(request.ranges);
    return sha256_hex(std::span(reinterpret_cast<const std::uint8_t*>(key.data()), key.size()));
}

fs::path RangeCache::entry_path(const std::string& key) const { return settings_.folder / key.substr(0, 2) / key; }

std::optional<std::vector<std::vector<std::uint8_t>>> RangeCache::find(const RangeRequest& request) {
    if (!enabled() || request.validator.empty()) return std::nullopt;
    const std::string key = entry_key(request);
    const fs::path path = entry_path(key);
    {
        std::lock_guard lock(mutex_);
        const auto q = queued_paths_.find(path.native());
        if (q != queued_paths_.end()) return ++hits_, q->second->parts;
    }
    if (settings_.pack_below > 0) {
        if (auto parts = find_packed(key, request)) return parts;
    }
    const EntryFile entry = read_entry(path, request);
    if (!entry.exists) return std::nullopt;
    if (!entry.problem.empty()) return drop(path, request, entry.problem), std::nullopt;
    auto parts = decode(entry.content, request);
    if (parts.index() == 1) return drop(path, request, std::get<1>(parts)), std::nullopt;
    std::error_code ec;
    fs::last_write_time(path, fs::file_time_type::clock::now(), ec);  // recently used
    std::lock_guard lock(mutex_);
    ++hits_;
    return std::move(std::get<0>(parts));
}

std::optional<RangeCache::Parts> RangeCache::find_packed(const std::string& key, const RangeRequest& request) {
    std::string record, problem;
    fs::path pack;
    PackSlot slot;
    bool touch = false;
    {
        std::lock_guard lock(mutex_);  // (held while read: an eviction closes the pack's descriptor)
        load_packs();
        const auto it = slots_.find(key_prefix(key));
        if (it == slots_.end()) return std::nullopt;
        slot = it->second;
        Pack& p = packs_[slot.pack];
        if (p.fd < 0) p.fd = ::open(p.path.c_str(), O_RDONLY | O_CLOEXEC);
        if (p.fd < 0) return slots_.erase(it), std::nullopt;  // (gone: another process evicted it)
        pack = p.path;
        if (slot.length > kKeyChars + max_entry_size(request)) {  // (not read: a record no request can have)
            problem = "its length, " + std::to_string(slot.length) + " bytes, is more than its ranges can hold";
        } else {
            record.resize(slot.length);
            if (!read_all(p.fd, record.data(), record.size(), slot.offset)) return slots_.erase(it), std::nullopt;
            touch = !std::exchange(p.touched, true);
        }
    }
    if (!problem.empty()) return drop_packed(pack, slot, key, request, problem);
    if (record.compare(0, kKeyChars, key) != 0) {  // another key of the same prefix, or a damaged key
        return record.size() < kKeyChars ? drop_packed(pack, slot, key, request, "it is cut short") : std::nullopt;
    }
    auto parts = decode(record.substr(kKeyChars), request);
    if (parts.index() == 1) return drop_packed(pack, slot, key, request, std::get<1>(parts));
    std::error_code ec;
    if (touch) fs::last_write_time(pack, fs::file_time_type::clock::now(), ec);  // recently used (once a process)
    std::lock_guard lock(mutex_);
    ++hits_;
    return std::move(std::get<0>(parts));
}

std::nullopt_t RangeCache::drop_packed(const fs::path& pack, const PackSlot& slot, const std::string& key,
                                       const RangeRequest& request, const std::string& why) {
    const std::string message = "the range cache record at byte " + std::to_string(slot.offset) + " of " +
                                pack.string() + " (" + described(request) + ") was dropped and fetched again: " + why;
    std::lock_guard lock(mutex_);
    if (const auto it = slots_.find(key_prefix(key)); it != slots_.end() && it->second.offset == slot.offset &&
                                                      it->second.pack == slot.pack) {
        slots_.erase(it);
    }
    diagnostics_.add({DiagnosticLevel::warning, pack.string(), slot.offset, message});
    return std::nullopt;
}

void RangeCache::load_packs() {
    if (std::exchange(packs_loaded_, true)) return;
    std::error_code ec;
    for (fs::directory_iterator it(settings_.folder / kPackFolder, ec), end; !ec && it != end; it.increment(ec)) {
        if (it->path().extension() != ".index") continue;
        Pack pack{fs::path(it->path()).replace_extension(".pack")};
        std::error_code fec;
        const std::uint64_t pack_size = fs::file_size(pack.path, fec);
        if (fec) continue;  // (an index without its pack: evicted, or being made)
        const int fd = ::open(it->path().c_str(), O_RDONLY | O_CLOEXEC);
        if (fd < 0) continue;
        struct stat st {};
        std::string index;
        if (::fstat(fd, &st) == 0) index.resize(static_cast<std::size_t>(st.st_size) / kIndexRecord * kIndexRecord);
        const bool read = read_all(fd, index.data(), index.size(), 0);
        ::close(fd);
        if (!read) continue;
        const auto id = static_cast<std::uint32_t>(packs_.size());
        packs_.push_back(std::move(pack));
        for (std::size_t at = 0; at < index.size(); at += kIndexRecord) {  // (a torn last record: left out)
            std::size_t field = at + kKeyChars;
            std::uint64_t offset = 0, length = 0;
            get_u64(index, field, offset), get_u64(index, field, length);
            if (offset > pack_size || length > pack_size - offset) continue;
            slots_[key_prefix(std::string_view(index).substr(at, kKeyChars))] = {id, offset, length};
        }
    }
}

void RangeCache::drop(const fs::path& path, const RangeRequest& request, const std::string& why) {
    std::error_code ec;
    fs::remove(path, ec);
    const std::string message = "the range cache entry " + path.string() + " (" + described(request) +
                                ") was dropped and fetched again: " + why;
    std::lock_guard lock(mutex_);
    diagnostics_.add({DiagnosticLevel::warning, path.string(), std::nullopt, message});
}

Diagnostics RangeCache::take_diagnostics() {
    std::lock_guard lock(mutex_);
    return std::exchange(diagnostics_, {});
}

void RangeCache::store(const RangeRequest& request, const RangeReply& reply) {
    if (!enabled() || request.validator.empty() || !reply.error.empty()) return;
    std::uint64_t bytes = 0;
    for (const auto& p : reply.parts) bytes += p.size();
    {
        std::lock_guard lock(mutex_);  // (room taken first, the reply copied outside the lock find() takes)
        if (queued_bytes_ != 0 && queued_bytes_ + bytes > kMaxQueuedBytes) return;  // (one larger than all: alone)
        queued_bytes_ += bytes;
    }
    std::string key = entry_key(request);
    fs::path path = entry_path(key);
    Queued entry{std::move(key), std::move(path), reply.parts, bytes};
    std::lock_guard lock(mutex_);
    queue_.push_back(std::move(entry));
    queued_paths_[queue_.back().path.native()] = &queue_.back();  // (the latest of a path: the same bytes)
    if (!writer_.joinable()) writer_ = std::thread([this] { write_queued(); });
    queued_.notify_one();
}

void RangeCache::flush() {
    std::unique_lock lock(mutex_);
    written_.wait(lock, [&] { return queue_.empty(); });
}

void RangeCache::write_queued() {
    // The cache's writes yield to the reads, the parse and the frames: a country's catalog and sidecar (360 MB
    // through SHA-256 and a copy) are written while its items are parsed on the same cores.
    lower_thread_priority(kWriterNice);
    std::unique_lock lock(mutex_);
    while (true) {
        queued_.wait(lock, [&] { return stopping_ || !queue_.empty(); });
        if (queue_.empty()) return;  // (stopping, and all written)
        const Queued& entry = queue_.front();  // (pushes behind it leave it where it is)
        lock.unlock();
        write(entry);
        lock.lock();
        queued_bytes_ -= entry.bytes;
        if (const auto q = queued_paths_.find(entry.path.native()); q != queued_paths_.end() && q->second == &entry) {
            queued_paths_.erase(q);
        }
        queue_.pop_front();
        written_.notify_all();
    }
}

void RangeCache::write(const Queued& entry) {
    if (entry.bytes < settings_.pack_below) {
        std::uint64_t written = 0;
        if (!append_to_pack(entry, written)) return;  // a cache that cannot be written only costs the next look
        std::lock_guard lock(mutex_);
        scan_total();
        total_ += written;
        return evict_if_needed();
    }
    const fs::path& path = entry.path;
    std::error_code ec;
    fs::create_directories(path.parent_path(), ec);
    const fs::path temp = path.string() + ".tmp" + std::to_string(::getpid());
    if (!staging_) staging_.reset(static_cast<std::uint8_t*>(std::aligned_alloc(kDirectAlignment, kStagingBytes)));
    bool written = false;
    struct stat st {};
    const bool large = entry.bytes >= kDirectMinBytes;  // (a small one through the page cache: no wait on the disk)
    for (const bool direct : {direct_writes_ && large, false}) {  // (a file system that refuses O_DIRECT: buffered)
        const int flags = O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC | (direct ? O_DIRECT : 0);
        const int fd = staging_ ? ::open(temp.c_str(), flags, 0644) : -1;
        if (fd < 0 && direct && errno == EINVAL) {
            direct_writes_ = false;
            continue;
        }
        if (fd < 0) return;  // a cache that cannot be written only costs the next look a request
        EntryOutput out(fd, staging_.get(), direct);
        written = write_entry(out, entry.parts) && ::fstat(fd, &st) == 0;
        const int error = errno;
        if (::close(fd) != 0) written = false;
        if (written || !direct || error != EINVAL) break;
        direct_writes_ = false;  // (accepted at open, refused at the write)
    }
    if (!written) return fs::remove(temp, ec), void();
    fs::rename(temp, path, ec);
    if (ec) return fs::remove(temp, ec), void();
    std::lock_guard lock(mutex_);
    scan_total();
    total_ += static_cast<std::uint64_t>(st.st_size);
    evict_if_needed();
}

bool RangeCache::append_to_pack(const Queued& entry, std::uint64_t& written) {
    std::uint32_t pack = 0;
    {
        std::lock_guard lock(mutex_);
        load_packs();  // (the packs before this process's first)
        const std::uint64_t limit = std::max<std::uint64_t>(1, std::min(kPackBytes, settings_.max_bytes / 16));
        if (writing_ && writing_size_ >= limit) writing_.reset();
    }
    if (!writing_ && !open_pack()) return false;
    std::string record = entry.key;
    put_entry([&](const void* data, std::size_t n) { return record.append(static_cast<const char*>(data), n), true; },
              entry.parts);
    std::string index = entry.key;
    put_u64(index, writing_size_);
    put_u64(index, record.size());
    {
        std::lock_guard lock(mutex_);  // (the descriptor is the writer's: only its own eviction closes it)
        pack = *writing_;
    }
    if (!write_all(packs_[pack].fd, record.data(), record.size(), writing_size_) ||
        !write_all(writing_index_fd_, index.data(), index.size())) {
        std::lock_guard lock(mutex_);
        writing_.reset();  // (a pack that failed a write takes no more)
        return false;
    }
    std::lock_guard lock(mutex_);
    slots_[key_prefix(entry.key)] = {pack, writing_size_, record.size()};
    writing_size_ += record.size();
    written = record.size() + index.size();
    return true;
}

bool RangeCache::open_pack() {
    std::error_code ec;
    const fs::path folder = settings_.folder / kPackFolder;
    fs::create_directories(folder, ec);
    if (writing_index_fd_ >= 0) ::close(std::exchange(writing_index_fd_, -1));
    const auto now = std::chrono::system_clock::now().time_since_epoch().count();
    const fs::path path = folder / (std::to_string(::getpid()) + "-" + std::to_string(now) + ".pack");
    const int fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
    if (fd < 0) return false;
    const fs::path index = fs::path(path).replace_extension(".index");
    writing_index_fd_ = ::open(index.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_APPEND | O_CLOEXEC, 0644);
    if (writing_index_fd_ < 0) return ::close(fd), fs::remove(path, ec), false;
    std::lock_guard lock(mutex_);
    writing_ = static_cast<std::uint32_t>(packs_.size());
    writing_size_ = 0;
    packs_.push_back({path, fd});
    return true;
}

void RangeCache::forget_pack(std::uint32_t pack) {
    Pack& p = packs_[pack];
    if (p.fd >= 0) ::close(std::exchange(p.fd, -1));
    std::erase_if(slots_, [&](const auto& slot) { return slot.second.pack == pack; });
    if (writing_ == pack) {
        writing_.reset();
        if (writing_index_fd_ >= 0) ::close(std::exchange(writing_index_fd_, -1));
    }
}

void RangeCache::scan_total() {
    if (scanned_) return;
    scanned_ = true;
    std::error_code ec;
    for (fs::recursive_directory_iterator it(settings_.folder, ec), end; !ec && it != end; it.increment(ec)) {
        std::error_code fec;
        if (it->is_regular_file(fec)) total_ += it->file_size(fec);
    }
}

void RangeCache::evict_if_needed() {
    if (total_ <= settings_.max_bytes) return;
    std::vector<std::pair<fs::file_time_type, fs::path>> entries;
    std::error_code ec;
    total_ = 0;
    for (fs::recursive_directory_iterator it(settings_.folder, ec), end; !ec && it != end; it.increment(ec)) {
        std::error_code fec;
        if (!it->is_regular_file(fec)) continue;
        entries.emplace_back(it->last_write_time(fec), it->path());
        total_ += it->file_size(fec);
    }
    std::sort(entries.begin(), entries.end());
    const std::uint64_t target = settings_.max_bytes / 10 * 9;  // room for a while before the next sweep
    for (const auto& [time, path] : entries) {
        if (total_ <= target) break;
        std::error_code fec;
        if (path.extension() == ".index" && path.parent_path().filename() == kPackFolder &&
            fs::exists(fs::path(path).replace_extension(".pack"), fec)) {
            continue;  // (removed with its pack; one whose pack is gone goes now)
        }
        const auto size = fs::file_size(path, fec);
        if (fec || !fs::remove(path, fec)) continue;
        total_ -= size;
        if (path.extension() != ".pack" || path.parent_path().filename() != kPackFolder) continue;
        const fs::path index = fs::path(path).replace_extension(".index");
        const auto index_size = fs::file_size(index, fec);
        if (!fec && fs::remove(index, fec)) total_ -= index_size;
        for (std::uint32_t k = 0; k < packs_.size(); ++k) {
            if (packs_[k].path == path) forget_pack(k);  // (again once evicted: nothing left to do)
        }
    }
}

std::uint64_t RangeCache::hits() const {
    std::lock_guard lock(mutex_);
    return hits_;
}

}  // namespace lidarscout::net
