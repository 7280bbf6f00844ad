// A file on an HTTP(S) server, read by range requests: its size and validator (ETag or
// Last-Modified) pinned by the first response, its first and last 2 KiB fetched when it is
// opened (a tile's header, VLRs and usually its chunk table: half of what local files keep,
// as every byte crosses the network), and exact reads anywhere else. Where the host is known to
// answer several ranges in one multipart response (it did so before; the first of the opens a prefetch
// of several files starts for a host not known yet asks so, and the others wait for its answer), a file
// opens in one request: its head and last 2 KiB together ("bytes=0-8191,-2048": the first 8 KiB until
// the host's LAS files showed the head they need; a small file's answer is the whole file), the head then
// kept as an open in two keeps it. Elsewhere (S3, hosts that answer one range), and where that answer
// could not be used, the head comes first, then the tail with the rest of a LAS head longer than 2 KiB
// (its VLRs and first point record, up to 64 KiB) in one request, and a small file's middle with them
// when that costs less than a request (then every read of it is answered from memory); a head longer
// than asked costs one request more either way (HttpStats: opens_in_one, open_fallbacks).
// Remote files are shared process-wide by URL, so a tile opened again (by the chunk-point
// loader, the viewer, a second command in the same process) costs no request, and every
// response for it is checked against the same validator and size (Content-Range's total: all a
// server without ETag and Last-Modified tells): a file that changes on the server during a
// session is an error, never a mix of two versions. URLs are shown without their
// credentials (display_url). An s3:// URL is read the same way, through its http(s) URL and
// signing (net/s3_request.hpp). Where redirects lead is kept per file: later requests go there
// directly, and a 403 there (an expired signed URL) resolves the file's own URL again, once.
#pragma once

#include <cstdint>
#include <functional>
#include <future>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "net/http_client.hpp"

namespace lidarscout::net {

class RemoteFile {
public:
    static constexpr std::uint64_t kEdge = 2048;

    // The remote file at `url`, opened (one request, or two: the head, then the rest of a LAS head and
    // the tail) on first use; throws Error.
    static std::shared_ptr<const RemoteFile> open(const std::string& url);
    // A file opened from its start, and its first bytes (open_from_start).
    struct FromStart {
        std::shared_ptr<const RemoteFile> file;
        std::vector<std::uint8_t> first;
    };
    // Starts opening `url` to be read from its start (a JSON document, not a LAS file: no tail is asked) and
    // returns at once: one request for its first `bytes`, which come with the file (its head keeps kEdge of them).
    // From the call on, an open() of `url` waits for this one. A file open or being opened already comes as it is,
    // with nothing beside it. The future throws Error.
    static std::future<FromStart> open_from_start(const std::string& url, std::uint64_t bytes);
    // Starts opening the files of `urls` not open yet, all requests in flight together, and
    // returns at once; open() of such a URL waits for its file. Failures are not reported
    // here: open() of that URL tries again and reports them.
    static void prefetch(std::span<const std::string> urls);
    // Forgets every open remote file: the next open() fetches its edges again (benchmarks).
    static void forget_all();

    const std::string& display_url() const { return display_url_; }
    std::uint64_t size() const { return size_; }
    const std::string& validator() const { return validator_; }
    // The Content-Type of the first response ("" when the server gave none), as the server wrote it.
    const std::string& content_type() const { return content_type_; }
    std::span<const std::uint8_t> head() const { return head_; }  // bytes [0, head().size()): kEdge or more
    std::span<const std::uint8_t> tail() const { return tail_; }  // bytes [size() - tail().size(), size())

    // Reads exactly out.size() bytes at `offset` (one range request); throws Error.
    void read(std::uint64_t offset, std::span<std::uint8_t> out) const;
    // The `size` bytes at `offset` as they came (one range request, no copy; written into `buffer` where its
    // capacity holds them: RangeRequest::buffer); throws Error.
    std::vector<std::uint8_t> read_bytes(std::uint64_t offset, std::uint64_t size,
                                         std::vector<std::uint8_t> buffer = {}) const;
    // The bytes of each range, fetched together (fetch_async: one request where the server allows it or they lie
    // close together), each whole; throws Error. `buffer`: RangeRequest::buffer of a request of one range.
    std::vector<std::vector<std::uint8_t>> read_ranges(std::vector<ByteRange> ranges,
                                                       std::vector<std::uint8_t> buffer = {}) const;
    // Fetches the ranges (multi-range where the server allows it); `done` runs on the
    // client's thread with one part per range, or with an error. Ranges the head or tail holds
    // are answered from them (when all are, `done` runs at once, on this thread, with no
    // request), and the others that lie close together go as one range (HttpSettings'
    // net/byte_ranges.hpp: merge_ranges). `buffer`: RangeRequest::buffer of a request of one range.
    void fetch_async(std::vector<ByteRange> ranges, HttpClient::Callback done,
                     std::vector<std::uint8_t> buffer = {}) const;

    // Fetches the ranges and waits; the reply's error is set when it failed.
    RangeReply fetch_now(std::vector<ByteRange> ranges, std::vector<std::uint8_t> buffer = {}) const;

    RemoteFile(std::string url, RangeReply&& head);  // from the reply to the head request
    // Takes the second reply of an open: the rest of the head (its first part, when `more_head`),
    // then the tail (when `tail`).
    void set_rest(bool more_head, bool tail, RangeReply&& reply);
    // Of an open in one request (the head and the tail asked together): its tail, and the head cut to
    // `bytes` (kEdge or more).
    void set_tail(std::vector<std::uint8_t> tail);
    void trim_head(std::uint64_t bytes);

    struct Redirect;  // where the file's redirects led

private:
    // The bytes of `r` when the head or the tail holds them all.
    std::optional<std::vector<std::uint8_t>> held(const ByteRange& r) const;

    std::string url_, display_url_, validator_, content_type_;
    std::shared_ptr<Redirect> redirect_;
    std::uint64_t size_ = 0;
    std::vector<std::uint8_t> head_, tail_;
};

}  // namespace lidarscout::net
