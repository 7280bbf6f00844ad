// s3:// URLs as requests: "s3://bucket/key" becomes the http(s) URL of the object
// (virtual-hosted "bucket.s3.REGION.amazonaws.com/key" or path-style "endpoint/bucket/key",
// net/s3_config.hpp) with the signing libcurl does (AWS Signature V4 through CURLOPT_AWS_SIGV4,
// the session token and requester-pays headers), or an anonymous request without credentials.
// A key is requested normalised, and refused when it leaves its bucket (net/url.hpp). A prefix
// "s3://bucket/prefix/" is listed with ListObjectsV2, every page (continuation tokens), within
// limits. Errors name the bucket, the key and the S3 error code.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "net/http_client.hpp"
#include "net/s3_config.hpp"

namespace lidarscout::net {

// True for "s3://..." (scheme case-insensitive).
bool is_s3_url(std::string_view url);

struct S3Location {
    std::string bucket, key;  // the key as stored (not percent-encoded); "" for a bucket's root
};
// The bucket and key of "s3://bucket/key"; nothing when `url` is not an s3 URL with a bucket.
std::optional<S3Location> parse_s3_url(std::string_view url);

// The http(s) URL of `where` ("?query" appended when given, its parameters already encoded and
// sorted by name, as Signature V4 needs them).
std::string s3_http_url(const S3Config& config, const S3Location& where, const std::string& query = {});

// The signing of requests made with `config` (unsigned, with only the requester-pays header,
// when it is anonymous).
RequestSigning s3_signing(const S3Config& config);

// A request for byte ranges of `url`: an http(s) URL as it is, an s3 URL through the process's
// S3 configuration, its key normalised (throws Error when `url` is s3 without a key, with a
// bucket name S3 does not allow, a key that leaves its bucket, or the configuration is bad).
RangeRequest remote_request(const std::string& url, std::vector<ByteRange> ranges, std::string validator);

// " (bucket \"b\", key \"k\")" for an s3 URL, "" for any other (for error messages).
std::string s3_error_context(std::string_view url);

struct S3Object {
    std::string key;  // normalised (net/url.hpp: normalise_s3_key)
    std::uint64_t size = 0;
};

// What one listing may cost, so that a hostile or broken server can make it neither endless nor
// unbounded in memory.
struct S3ListLimits {
    unsigned page_size = 1000;                    // keys asked per page (max-keys): a page with more is refused
    std::uint64_t max_pages = 5000;               // pages, those without keys included
    std::uint64_t max_keys = 4'000'000;           // keys listed (as many items as a STAC catalog may hold)
    std::uint64_t max_kept_bytes = 256ull << 20;  // bytes of the keys kept, together
    std::uint64_t max_page_bytes = 8ull << 20;    // bytes of one page (1,000 keys of 1,024 bytes take 1.4 MiB)
    std::size_t max_token = 4096;                 // bytes of one continuation token
};

// Called with each object listed, in key order; returns whether it keeps it (its key then
// counts toward S3ListLimits::max_kept_bytes).
using S3ObjectVisitor = std::function<bool(S3Object&&)>;

// Lists every object whose key starts with the key of `url` ("s3://bucket/prefix/") with
// ListObjectsV2, page after page (continuation tokens), calling `take` with each; returns how
// many keys were listed. Throws Error, one line naming the bucket and prefix and the cause, when
// a page cannot be listed (with the S3 error code) or the server breaks the protocol or the
// limits: a page larger than max_page_bytes or holding more keys than asked, a key not after the
// one before it, longer than 1,024 bytes, or leaving its bucket or the prefix (however spelled:
// normalise_s3_key), a truncated page without a continuation token, a token longer than
// max_token or given before, more than max_pages pages, max_keys keys or max_kept_bytes.
std::uint64_t for_each_s3_object(const std::string& url, const S3ObjectVisitor& take,
                                 const S3ListLimits& limits = {});

// Every object under the prefix of `url`, in key order (for_each_s3_object, all kept).
std::vector<S3Object> list_s3_objects(const std::string& url, const S3ListLimits& limits = {});

}  // namespace lidarscout::net
