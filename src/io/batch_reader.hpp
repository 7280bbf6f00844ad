// Many small positioned reads in flight: a source hands out read requests in the order it
// wants them served (it may change its mind between calls) and receives each result. Two
// back ends: io_uring (liburing; a few threads, each with a ring of `queue_depth` reads in
// flight) and a thread pool of blocking pread calls for kernels where io_uring is missing or
// forbidden. With `direct` the reads are widened to 4 KiB-aligned sectors into aligned
// buffers, as O_DIRECT file descriptors need; the source still sees only the bytes it asked
// for.
//
// A request may name a remote file instead of a descriptor: those go out as HTTP range
// requests (io/remote_reads.hpp), the consecutive requests for one file grouped into one
// multi-range request, alongside the local reads of the same run.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>

#include "core/error.hpp"

namespace lidarscout::net {
class RemoteFile;
}

namespace lidarscout::io {

struct ReadRequest {
    int fd = -1;
    std::uint64_t offset = 0;
    std::uint32_t length = 0;
    std::uint64_t tag = 0;  // the source's own identifier
    const net::RemoteFile* remote = nullptr;  // set: read from this remote file (fd unused)
    const std::string* path = nullptr;        // the file's name, for errors (ReadTarget sets it)
};

// What a source's requests read: a local file's descriptor (owned; O_DIRECT when asked and
// the file system has it) or a remote file (path an http(s) URL).
class ReadTarget {
public:
    // Throws lidarscout::Error when the path cannot be opened or is not a regular file.
    static ReadTarget open(const std::string& path, bool direct);

    ReadTarget() = default;
    ReadTarget(ReadTarget&& other) noexcept;
    ReadTarget& operator=(ReadTarget&& other) noexcept;
    ReadTarget(const ReadTarget&) = delete;
    ReadTarget& operator=(const ReadTarget&) = delete;
    ~ReadTarget();

    // A request for `length` bytes at `offset` of this target.
    ReadRequest request(std::uint64_t offset, std::uint32_t length, std::uint64_t tag) const;

private:
    int fd_ = -1;
    std::shared_ptr<const net::RemoteFile> remote_;
    std::shared_ptr<const std::string> path_;  // shared: requests point to it, the target may move
};

class ReadSource {
public:
    virtual ~ReadSource() = default;
    // Fills up to out.size() requests in the order they should be read; returns how many.
    // Returning 0 means no more requests will come (done or cancelled). Thread-safe.
    virtual std::size_t next(std::span<ReadRequest> out) = 0;
    // The result of one request: `data` holds exactly `request.length` bytes and `error` is
    // null, or `data` is empty and `error` says why not (the request's file and offset, and the
    // cause). Called from reader threads, concurrently.
    virtual void complete(const ReadRequest& request, std::span<const std::uint8_t> data, const ErrorRecord* error) = 0;
};

// The failure of `request`: its file (when the request names one), its offset and `cause`.
ErrorRecord read_error(const ReadRequest& request, std::string cause);
// The cause of a read that got fewer bytes than it asked for.
inline constexpr const char* kShortRead = "short read: the file ends before the requested record";

enum class ReadBackend { Auto, IoUring, Pread };

const char* backend_name(ReadBackend backend);  // "auto", "io_uring", "pread"

struct BatchReadOptions {
    ReadBackend backend = ReadBackend::Auto;  // Auto: io_uring when the kernel allows it
    unsigned threads = 0;        // io_uring: rings (0: hardware threads); pread: threads (0: queue_depth)
    unsigned queue_depth = 64;   // io_uring: reads in flight per ring
    bool direct = false;         // widen reads to aligned 4 KiB sectors (for O_DIRECT descriptors)
    unsigned http_in_flight = 256;      // remote requests: HTTP requests out at once
    std::size_t http_max_ranges = 256;  // remote requests: ranges in one multi-range request
};

// True when an io_uring instance can be created here.
bool io_uring_available();

// Serves the source until it returns 0 and every read handed out has completed. Returns the
// back end that ran (IoUring or Pread). Throws Error when IoUring is requested but absent.
ReadBackend run_batch_reads(ReadSource& source, const BatchReadOptions& options);

}  // namespace lidarscout::io
