// The on-disk range cache: entry files (a count, then each part's length and bytes),
// written under a temporary name and renamed, evicted least recently used first.
#include "net/range_cache.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <memory>

#include "core/sha256.hpp"

namespace lidarscout::net {

namespace fs = std::filesystem;

namespace {

constexpr std::uint64_t kMaxParts = 1u << 20;

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

// The parts of an entry file's content, or nothing when it is damaged or does not fit `request`.
std::optional<std::vector<std::vector<std::uint8_t>>> decode(const std::string& in, const RangeRequest& request) {
    std::size_t at = 0;
    std::uint64_t n = 0;
    if (!get_u64(in, at, n) || n != request.ranges.size() || n > kMaxParts) return std::nullopt;
    std::vector<std::vector<std::uint8_t>> parts(n);
    for (std::uint64_t i = 0; i < n; ++i) {
        std::uint64_t len = 0;
        if (!get_u64(in, at, len) || len > request.ranges[i].length || len > in.size() - at) return std::nullopt;
        parts[i].assign(in.begin() + at, in.begin() + at + len);
        at += len;
    }
    if (at != in.size()) return std::nullopt;
    return parts;
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
    std::ifstream in(path, std::ios::binary);
    if (!in) return std::nullopt;
    const std::string content{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    auto parts = decode(content, request);
    std::error_code ec;
    if (!parts) {
        fs::remove(path, ec);  // damaged: fetched again
        return std::nullopt;
    }
    fs::last_write_time(path, fs::file_time_type::clock::now(), ec);  // recently used
    std::lock_guard lock(mutex_);
    ++hits_;
    return parts;
}

void RangeCache::store(const RangeRequest& request, const RangeReply& reply) {
    if (!enabled() || request.validator.empty() || !reply.error.empty()) return;
    std::string content;
    put_u64(content, reply.parts.size());
    for (const auto& p : reply.parts) {
        put_u64(content, p.size());
        content.append(p.begin(), p.end());
    }
    const fs::path path = entry_path(request);
    std::error_code ec;
    fs::create_directories(path.parent_path(), ec);
    const fs::path temp = path.string() + ".tmp" + std::to_string(::getpid());
    {
        std::ofstream out(temp, std::ios::binary | std::ios::trunc);
        out.write(content.data(), static_cast<std::streamsize>(content.size()));
        if (!out) {
            fs::remove(temp, ec);
            return;  // a cache that cannot be written only costs the next look a request
        }
    }
    fs::rename(temp, path, ec);
    if (ec) return fs::remove(temp, ec), void();
    std::lock_guard lock(mutex_);
    scan_total();
    total_ += content.size();
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
