// io::File: POSIX for local files (open O_RDONLY, regular files only, fstat, pread loop), range requests for URLs.
#include "io/file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <algorithm>
#include <cstring>
#include <utility>

#include "core/error.hpp"
#include "core/regular_file.hpp"
#include "net/remote_file.hpp"
#include "net/url.hpp"

namespace lidarscout::io {

std::string display_path(const std::string& path) { return net::redact_url(path); }

File File::of_remote(std::shared_ptr<const net::RemoteFile> remote) {
    File f;
    f.remote_ = std::move(remote);
    f.path_ = f.remote_->display_url();
    f.size_ = f.remote_->size();
    const auto head = f.remote_->head(), tail = f.remote_->tail();
    f.head_.assign(head.begin(), head.end());
    f.tail_.assign(tail.begin(), tail.end());
    return f;
}

void File::prefetch(std::span<const std::string> paths) { net::RemoteFile::prefetch(paths); }

std::future<std::pair<File, std::vector<std::uint8_t>>> File::open_from_start(const std::string& path,
                                                                               std::size_t first_bytes) {
    if (!net::is_url(path)) {
        return std::async(std::launch::deferred, [path] { return std::pair{open(path), std::vector<std::uint8_t>()}; });
    }
    return std::async(std::launch::deferred, [opening = net::RemoteFile::open_from_start(path, first_bytes)]() mutable {
        net::RemoteFile::FromStart opened = opening.get();
        return std::pair{of_remote(std::move(opened.file)), std::move(opened.first)};
    });
}

File File::open(const std::string& path) {
    if (net::is_url(path)) return of_remote(net::RemoteFile::open(path));
    File f;
    f.path_ = path;
    f.fd_ = open_regular_file(path);  // a FIFO, device or folder refused before a read could hang
    if (f.fd_ < 0) throw Error(path, std::nullopt, std::string("cannot open: ") + std::strerror(errno));
    struct stat st {};
    if (::fstat(f.fd_, &st) != 0) throw Error(path, std::nullopt, std::string("cannot stat: ") + std::strerror(errno));
    f.size_ = static_cast<std::uint64_t>(st.st_size);
    f.head_.resize(static_cast<std::size_t>(std::min<std::uint64_t>(f.size_, kCachedEdge)));
    f.head_.resize(f.read_uncached(0, f.head_));
    if (f.size_ > 2 * kCachedEdge) {
        f.tail_.resize(kCachedEdge);
        f.tail_.resize(f.read_uncached(f.size_ - kCachedEdge, f.tail_));
    }
    return f;
}

File File::in_memory(std::string path, std::uint64_t size, std::vector<std::uint8_t> head,
                     std::vector<std::uint8_t> tail) {
    File f;
    f.path_ = std::move(path);
    f.size_ = size;
    f.head_ = std::move(head);
    f.tail_ = std::move(tail);
    if (f.head_.size() > size || f.tail_.size() > size) throw Error(f.path_, std::nullopt, "held bytes past its size");
    return f;
}

File::File(File&& other) noexcept { *this = std::move(other); }

File& File::operator=(File&& other) noexcept {
    if (this != &other) {
        if (fd_ >= 0) ::close(fd_);
        path_ = std::move(other.path_);
        fd_ = std::exchange(other.fd_, -1);
        size_ = std::exchange(other.size_, 0);
        head_ = std::move(other.head_);
        tail_ = std::move(other.tail_);
        remote_ = std::move(other.remote_);
    }
    return *this;
}

File::~File() {
    if (fd_ >= 0) ::close(fd_);
}

const std::uint8_t* File::cached(std::uint64_t offset, std::size_t n) const {
    // (written without offset + size, which a malformed offset could overflow)
    if (offset <= head_.size() && n <= head_.size() - offset) return head_.data() + offset;
    const std::uint64_t tail_start = size_ - tail_.size();
    if (!tail_.empty() && offset >= tail_start && offset <= size_ && n <= size_ - offset) {
        return tail_.data() + (offset - tail_start);
    }
    return nullptr;
}

std::span<const std::uint8_t> File::held(std::uint64_t offset, std::size_t n) const {
    const std::uint8_t* bytes = cached(offset, n);
    return bytes ? std::span(bytes, n) : std::span<const std::uint8_t>();
}

bool File::read_cached(std::uint64_t offset, std::span<std::uint8_t> out) const {
    const std::uint8_t* bytes = cached(offset, out.size());
    if (bytes) std::memcpy(out.data(), bytes, out.size());
    return bytes != nullptr;
}

std::size_t File::read_at(std::uint64_t offset, std::span<std::uint8_t> out) const {
    if (out.empty() || offset >= size_) return 0;  // past the end (as sized when opened)
    if (read_cached(offset, out)) return out.size();
    return read_uncached(offset, out);
}

std::size_t File::read_uncached(std::uint64_t offset, std::span<std::uint8_t> out) const {
    if (remote_) {
        const std::size_t n = static_cast<std::size_t>(std::min<std::uint64_t>(out.size(), size_ - offset));
        remote_->read(offset, out.first(n));
        return n;
    }
    if (fd_ < 0) throw Error(path_, offset, "a read outside the bytes held in memory (the file was not opened)");
    std::size_t done = 0;
    while (done < out.size()) {
        ssize_t n = ::pread(fd_, out.data() + done, out.size() - done, static_cast<off_t>(offset + done));
        if (n < 0) {
            if (errno == EINTR) continue;
            throw Error(path_, offset + done, std::string("read failed: ") + std::strerror(errno));
        }
        if (n == 0) break;
        done += static_cast<std::size_t>(n);
    }
    return done;
}

void File::read_exact(std::uint64_t offset, std::span<std::uint8_t> out, const char* what) const {
    std::size_t n = read_at(offset, out);
    if (n != out.size()) {
        throw Error(path_, offset,
                    std::string("file ends before the end of the ") + what + " (needed " +
                        std::to_string(out.size()) + " bytes, file has " + std::to_string(n) + ")");
    }
}

std::vector<std::vector<std::uint8_t>> File::read_ranges(
    std::span<const std::pair<std::uint64_t, std::uint64_t>> ranges, const char* what) const {
    std::vector<std::vector<std::uint8_t>> out;
    const bool fetch = remote_ && std::any_of(ranges.begin(), ranges.end(), [&](const auto& r) {
        return r.second > 0 && !cached(r.first, r.second);
    });
    if (fetch) {
        std::vector<net::ByteRange> asked;
        for (const auto& [offset, n] : ranges) {
            check_within(offset, n, what);
            if (n > 0) asked.push_back({offset, n});
        }
        auto parts = remote_->read_ranges(std::move(asked));
        for (std::size_t k = 0, part = 0; k < ranges.size(); ++k) {
            out.push_back(ranges[k].second > 0 ? std::move(parts[part++]) : std::vector<std::uint8_t>{});
        }
        return out;
    }
    for (const auto& [offset, n] : ranges) out.push_back(read_vector(offset, static_cast<std::size_t>(n), what));
    return out;
}

void File::check_within(std::uint64_t offset, std::uint64_t n, const char* what) const {
    if (offset > size_ || n > size_ - offset) {
        throw Error(path_, offset,
                    std::string("the ") + what + " (" + std::to_string(n) +
                        " bytes) extends beyond the end of the file (" + std::to_string(size_) + " bytes)");
    }
}

std::vector<std::uint8_t> File::read_vector(std::uint64_t offset, std::size_t n, const char* what,
                                            std::vector<std::uint8_t> buffer) const {
    check_within(offset, n, what);
    // A remote file's bytes as the response brought them (a catalog's 8 MB blocks, a sidecar: not copied again).
    if (remote_ && n != 0 && !cached(offset, n)) return remote_->read_bytes(offset, n, std::move(buffer));
    buffer.resize(n);
    read_exact(offset, buffer, what);
    return buffer;
}

}  // namespace lidarscout::io
