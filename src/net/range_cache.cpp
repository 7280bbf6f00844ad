// The on-disk range cache: entry files (a magic, a count, then each part's length, SHA-256 and
// bytes), written under a temporary name (around the page cache where the file system allows) and renamed by
// a thread of its own, checked when read, evicted least
// recently used first.
#include "net/range_cache.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <iterator>
#include <memory>
#include <string_view>
#include <utility>
#include <variant>

#include "core/sha256.hpp"
#include "net/url.hpp"

namespace lidarscout::net {

namespace fs = std::filesystem;

namespace {

constexpr std::uint64_t kMaxParts = 1u << 20;
constexpr std::string_view kMagic = "LSRANGE2";   // the entry format (8 bytes)
constexpr std::size_t kDigest = 64;               // a part's SHA-256, in hex
constexpr std::size_t kStagingBytes = RangeCache::kStagingBytes;
constexpr std::size_t kDirectAlignment = RangeCache::kDirectAlignment;

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
        for (std::size_t at = 0; at < n;) {
            const ssize_t done = ::write(fd_, staging_ + at, n - at);
            if (done < 0 && errno == EINTR) continue;
            if (done <= 0) return false;
            at += static_cast<std::size_t>(done);
        }
        written_ += n, filled_ = 0;
        return true;
    }

    int fd_;
    std::uint8_t* staging_;
    bool direct_;
    std::size_t filled_ = 0;
    std::uint64_t written_ = 0;
};

// Writes the entry file for `parts` (a reply's): magic, part count, then each part's length, SHA-256 and bytes;
// false when it could not be.
bool write_entry(EntryOutput& out, const std::vector<std::vector<std::uint8_t>>& parts) {
    std::string head(kMagic);
    put_u64(head, parts.size());
    for (const auto& p : parts) {
        put_u64(head, p.size());
        head += digest(p.data(), p.size());
        if (!out.put(head.data(), head.size()) || !out.put(p.data(), p.size())) return false;
        head.clear();
    }
    return out.put(head.data(), head.size()) && out.finish();
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
        std::size_t done = 0;
        while (done < entry.content.size()) {
            const ssize_t got = ::pread(fd, entry.content.data() + done, entry.content.size() - done,
                                        static_cast<off_t>(done));
            if (got <= 0) break;
            done += static_cast<std::size_t>(got);
        }
        if (done != entry.content.size()) entry.problem = "it could not be read whole";
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

fs::path RangeCache::entry_path(const RangeRequest& request) const {
    const std::string key = request.url + '\n' + request.validator + '\n' + range_header(request.ranges);
    const std::string hex = sha256_hex(std::span(reinterpret_cast<const std::uint8_t*>(key.data()), key.size()));
    return settings_.folder / hex.substr(0, 2) / hex;
}

std::optional<std::vector<std::vector<std::uint8_t>>> RangeCache::find(const RangeRequest& request) {
    if (!enabled() || request.validator.empty()) return std::nullopt;
    const fs::path path = entry_path(request);
    {
        std::lock_guard lock(mutex_);
        const auto q = queued_paths_.find(path.native());
        if (q != queued_paths_.end()) return ++hits_, q->second->parts;
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

void RangeCache::drop(const fs::path& path, const RangeRequest& request, const std::string& why) {
    std::error_code ec;
    fs::remove(path, ec);
    const auto& first = request.ranges.front();
    const std::string ranges = request.ranges.size() == 1
                                   ? "bytes " + std::to_string(first.offset) + "-" + std::to_string(first.last())
                                   : std::to_string(request.ranges.size()) + " ranges";
    const std::string message = "the range cache entry " + path.string() + " (" + redact_url(request.url) + ", " +
                                ranges + ") was dropped and fetched again: " + why;
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
    Queued entry{entry_path(request), reply.parts, bytes};
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
        const auto size = fs::file_size(path, fec);
        if (!fec && fs::remove(path, fec)) total_ -= size;
    }
}

std::uint64_t RangeCache::hits() const {
    std::lock_guard lock(mutex_);
    return hits_;
}

}  // namespace lidarscout::net
