// The HTTP client: byte ranges of http(s) URLs fetched with libcurl's multi interface on one
// background thread, many requests in flight (HTTP/2 multiplexing where the server offers
// it, otherwise a pool of keep-alive connections per host). A request asks for one or more
// ranges of one URL; several ranges go out as one multi-range request, answered as
// multipart/byteranges, or as single-range requests for hosts that do not answer those (and for
// S3 from the start: RangeRequest::one_range).
//
// Every response is validated: status 206, a Content-Range equal to what was asked (a range
// may only be shortened at the end of the file), exactly the bytes asked, and the same ETag
// (or Last-Modified) and file size (Content-Range's total) as the caller pinned. A server that
// ignores Range (status 200) is an error, and its body is not downloaded; neither is any
// response larger than asked. The body of an error status is read (up to 16 KiB) for the cause
// it names (an S3 error code), every text of it shown cut and redacted (net/server_text.hpp).
// A 206 is accepted on its Content-Range alone (no Accept-Ranges header is required).
// Time-outs, dropped connections, 429 and 5xx are retried with exponential backoff; a cut
// single-range body resumes where it stopped. TLS peers are verified against the system CA
// store (or the CAs of HttpSettings::ca_file), and redirects may not change the scheme or
// (unless allowed, net/origin_policy.hpp) the origin. A request has a deadline that grows
// with the bytes it asks for (a minimum rate after a grace period), so a server trickling its
// body cannot hold a request for long.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "net/byte_ranges.hpp"

namespace lidarscout::net {

struct HttpSettings {
    unsigned retries = 5;                            // further attempts after a retryable failure
    std::chrono::milliseconds backoff{200};          // before the first retry; doubled each time
    long connect_timeout_s = 15;
    long stall_timeout_s = 30;                       // a transfer receiving nothing this long is retried
    // The deadline of a request's bytes: `deadline_grace` plus the bytes asked at `min_rate`
    // bytes per second (all attempts together); a request past it fails. 0: no deadline.
    std::uint64_t min_rate = 16 * 1024;
    std::chrono::milliseconds deadline_grace{30'000};
    unsigned connections_per_host = 256;             // HTTP/1.1 keep-alive pool size (latency-bound reads)
    std::size_t max_range_header = 6000;             // characters of one Range header
    std::string ca_file;                             // PEM CAs to verify TLS peers with ("" = the system's)
    // Ranges of one remote read (net/remote_file.hpp) at most this many bytes apart go as one range
    // (net/byte_ranges.hpp: merge_ranges): for servers that answer one range per request (S3), where
    // each range costs a request, and for those that answer several at once, where each costs a part's
    // framing (~100 bytes). A request at a 50 ms round trip with 256 in flight takes what 20 KB take
    // at 100 MB/s, and S3 bills a GET as it bills 4.4 KB of egress: 16 KiB between the two
    // (`bench_http --replica --merge-gaps` prints both for a replica's chunk points). A remote file
    // whose middle is within it is read whole when opened.
    std::uint64_t merge_gap_one_range = 16 * 1024;
    std::uint64_t merge_gap_multi_range = 128;
};

// How a request is signed: AWS Signature V4 computed by libcurl itself (CURLOPT_AWS_SIGV4),
// and the headers it adds (x-amz-security-token, x-amz-request-payer, ...). Never shown.
struct RequestSigning {
    std::string aws_sigv4;             // "aws:amz:REGION:s3"; "" = not signed
    std::string access_key, secret;    // the signing credentials
    std::vector<std::string> headers;  // "Name: value" lines sent with the request (signed too)
};

struct RangeRequest {
    std::string url;                 // the file's name (shown redacted, the cache's key); may carry credentials
    std::vector<ByteRange> ranges;   // at least one
    std::string validator;           // ETag or Last-Modified that responses must carry ("" = any)
    // The file's size that responses' Content-Range must give (pinned by the first response): a
    // server that sends no validator still cannot switch files unnoticed. Nothing: any.
    std::optional<std::uint64_t> total;
    std::string target;              // the http(s) URL asked ("" = url): an s3:// file's, a redirect's end
    RequestSigning signing;
    // The target's path is sent exactly as built (an S3 key's, normalised by net/url.hpp), never
    // tidied by libcurl (CURLOPT_PATH_AS_IS).
    bool path_as_is = false;
    // A plain GET of a whole (small) response, status 200 and no Range: ranges holds one range
    // {0, the most bytes accepted}, and parts[0] the body (an S3 listing).
    bool whole = false;
    // The server answers one range per request (S3's GetObject): several ranges go as several
    // requests from the start, never first as one multi-range request.
    bool one_range = false;
    // Also the file's last `suffix` bytes ("-M" after the ranges, in the same request: a remote file's
    // head and tail in one request, net/remote_file.hpp), their part last in the reply. Such a request is
    // never split: an answer that is not multipart fails it (a 200 then marks the host as one that does
    // not answer several ranges), but a 200 no larger than what was asked is taken as the whole file
    // (nginx answers so when the ranges add up to more than the file): RangeReply::whole_file.
    std::uint64_t suffix = 0;
    // Memory the body of a request of one range is written into (its capacity kept, its bytes not: empty): a
    // reader's used block, whose pages are the process's already (fresh 8 MB blocks' page faults were 159 of the
    // network thread's 311 samples while a country's catalog came). Copies of a request hold none.
    std::vector<std::uint8_t> buffer;
    const std::string& asked() const { return target.empty() ? url : target; }
};

struct RangeReply {
    std::vector<std::vector<std::uint8_t>> parts;  // one per range asked; shorter only at the end of the file
    std::optional<std::uint64_t> total;            // the file's size, from Content-Range
    std::string validator;                         // ETag (or Last-Modified) of the responses
    std::string error;                             // non-empty: the request failed (after retries)
    long status = 0;                               // the last response's HTTP status (0: none)
    std::string final_url;                         // where redirects led, when they did ("" = none)
    std::string content_type;                      // the Content-Type of a reply not in parts ("" = none)
    bool whole_file = false;                       // parts holds one part: the whole file (a `suffix` request)
};

struct HttpStats {
    std::uint64_t requests = 0;        // HTTP requests sent (retries included)
    std::uint64_t body_bytes = 0;      // response bytes received (bodies, multipart framing included)
    std::uint64_t header_bytes = 0;    // response header bytes received
    std::uint64_t retries = 0;
    std::uint64_t http2_responses = 0; // attempts answered over HTTP/2
    std::uint64_t connections = 0;     // connections opened (a multiplexed one serves many requests)
    std::uint64_t peak_transfers = 0;  // most transfers in libcurl at once (one origin: connections_per_host)
    // Opens of remote files (net/remote_file.hpp) in one request, and those that asked in one and needed
    // more (a head longer than guessed, an answer that was not multipart: then in two, as S3's are).
    std::uint64_t opens_in_one = 0, open_fallbacks = 0;
};

class HttpClient {
public:
    using Callback = std::function<void(RangeReply&&)>;

    explicit HttpClient(HttpSettings settings = {});
    ~HttpClient();  // abandons requests in flight (their callbacks are not called)
    HttpClient(const HttpClient&) = delete;
    HttpClient& operator=(const HttpClient&) = delete;

    // The process's client, shared by every remote file.
    static HttpClient& shared();

    // Starts the request; `done` runs on the client's thread when it has succeeded or failed.
    void submit(RangeRequest request, Callback done);
    // Submits and waits.
    RangeReply fetch(RangeRequest request);

    void set_settings(const HttpSettings& settings);  // for requests submitted afterwards
    HttpSettings settings() const;
    HttpStats stats() const;
    // Whether requests to `url`'s origin may ask several ranges at once (false once it answered a
    // multi-range request otherwise).
    bool answers_multi_range(const std::string& url) const;
    // What requests to `url`'s origin have shown: that it answers several ranges in one multipart
    // response (yes), that it does not (no), or nothing yet.
    enum class MultiRange { unknown, yes, no };
    MultiRange multi_range(const std::string& url) const;
    // Counts an open that asked in one request (HttpStats::opens_in_one, or open_fallbacks when not `in_one`).
    void count_open(bool in_one);

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace lidarscout::net
