// Read-only random-access file: positioned reads (pread) that are safe to issue from
// many threads at once. We never open a user's input for writing. The first and last 4 KiB
// are read once when the file is opened and served from memory afterwards: a tile's header,
// VLRs, chunk-table pointer and (usually) its chunk table live there, so reading a tile's
// metadata costs two reads instead of six.
//
// A path that is an http(s) URL opens a remote file (net/remote_file.hpp): the same reads,
// served by range requests, the edges fetched when it is opened. path() is then the URL
// without credentials. Every stage above io/ reads local and remote files through this one
// class.
#pragma once

#include <cstdint>
#include <future>
#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace lidarscout::net {
class RemoteFile;
}

namespace lidarscout::io {

// `path` as shown to users: a URL without its credentials, a file path as it is.
std::string display_path(const std::string& path);

class File {
public:
    // Opens `path` (a file or an http(s) URL) read-only; throws lidarscout::Error if it cannot, or
    // when a local path is not a regular file (a FIFO, device, socket or folder: refused before any
    // read could wait forever, core/regular_file.hpp).
    static File open(const std::string& path);
    // Starts opening `path` to be read from its start (a document read whole) and returns at once: a remote one in
    // one request for its first `first_bytes`, which come with it (none for a file open already; a local one opens
    // as open() opens it, when the future is asked); an open() of it waits for this one. The future throws
    // lidarscout::Error as open() does.
    static std::future<std::pair<File, std::vector<std::uint8_t>>> open_from_start(const std::string& path,
                                                                                    std::size_t first_bytes);
    // Starts opening the remote files among `paths` together (many requests in flight) and
    // returns at once; the open() calls that follow wait only for their own file. Local paths
    // are left alone. Reports no error.
    static void prefetch(std::span<const std::string> paths);
    // A file of `size` bytes known only by its first bytes `head` and its last bytes `tail` (a tile's
    // metadata as an overview sidecar holds it: dataset/overview_sidecar.hpp); a read elsewhere throws
    // Error naming `path`.
    static File in_memory(std::string path, std::uint64_t size, std::vector<std::uint8_t> head,
                          std::vector<std::uint8_t> tail);

    File() = default;
    File(File&& other) noexcept;
    File& operator=(File&& other) noexcept;
    File(const File&) = delete;
    File& operator=(const File&) = delete;
    ~File();

    const std::string& path() const noexcept { return path_; }
    std::uint64_t size() const noexcept { return size_; }
    int fd() const noexcept { return fd_; }  // -1 for a remote file
    const std::shared_ptr<const net::RemoteFile>& remote() const noexcept { return remote_; }

    // Reads up to out.size() bytes at `offset`; returns how many were read (short at EOF).
    std::size_t read_at(std::uint64_t offset, std::span<std::uint8_t> out) const;
    // Reads exactly out.size() bytes at `offset` or throws an Error naming what was missing.
    void read_exact(std::uint64_t offset, std::span<std::uint8_t> out,
                    const char* what = "data") const;
    // `buffer`: memory the bytes may be written into (its capacity kept; a reader's used block, whose pages are the
    // process's already: fresh ones cost a page fault each, and a country's 250 MB catalog came in 8 MB blocks).
    std::vector<std::uint8_t> read_vector(std::uint64_t offset, std::size_t n, const char* what = "data",
                                          std::vector<std::uint8_t> buffer = {}) const;
    // The bytes of each range (offset, size), read together: a remote file's in one fetch (multi-range, or as one
    // range where they lie close together: net::RemoteFile::read_ranges) where its edges do not hold them all, a
    // local one's a read each. Throws Error when one is not there whole.
    std::vector<std::vector<std::uint8_t>> read_ranges(std::span<const std::pair<std::uint64_t, std::uint64_t>> ranges,
                                                       const char* what = "data") const;
    // The bytes [offset, offset + n) where the file holds them in memory (its edges; an in-memory file's head), as
    // a view valid while the file lives; empty when they are not all held.
    std::span<const std::uint8_t> held(std::uint64_t offset, std::size_t n) const;

    static constexpr std::size_t kCachedEdge = 4096;

private:
    static File of_remote(std::shared_ptr<const net::RemoteFile> remote);
    // Copies [offset, offset + out.size()) from a cached edge; false when not fully inside one.
    bool read_cached(std::uint64_t offset, std::span<std::uint8_t> out) const;
    // Where the head or tail held in memory has the `n` bytes at `offset`; null when it has not.
    const std::uint8_t* cached(std::uint64_t offset, std::size_t n) const;
    // Throws an Error naming `what` unless [offset, offset + n) lies within the file.
    void check_within(std::uint64_t offset, std::uint64_t n, const char* what) const;
    std::size_t read_uncached(std::uint64_t offset, std::span<std::uint8_t> out) const;

    std::string path_;
    // first / last kCachedEdge bytes (remote: its edges; tail empty for small files)
    std::vector<std::uint8_t> head_, tail_;
    int fd_ = -1;
    std::shared_ptr<const net::RemoteFile> remote_;
    std::uint64_t size_ = 0;
};

}  // namespace lidarscout::io
