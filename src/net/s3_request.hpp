// s3:// URLs as requests: "s3://bucket/key" becomes the http(s) URL of the object
// (virtual-hosted "bucket.s3.REGION.amazonaws.com/key" or path-style "endpoint/bucket/key",
// net/s3_config.hpp) with the signing libcurl does (AWS Signature V4 through CURLOPT_AWS_SIGV4,
// the session token and requester-pays headers), or an anonymous request without credentials.
// A prefix "s3://bucket/prefix/" is listed with ListObjectsV2, every page (continuation
// tokens). Errors name the bucket, the key and the S3 error code.
#pragma once

#include <cstdint>
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
// S3 configuration (throws Error when `url` is s3 without a key, or the configuration is bad).
RangeRequest remote_request(const std::string& url, std::vector<ByteRange> ranges, std::string validator);

// " (bucket \"b\", key \"k\")" for an s3 URL, "" for any other (for error messages).
std::string s3_error_context(std::string_view url);

struct S3Object {
    std::string key;
    std::uint64_t size = 0;
};

// Every object whose key starts with the key of `url` ("s3://bucket/prefix/"), in key order,
// asking `page_size` keys a time (ListObjectsV2 pages, until one is not truncated); throws Error
// naming the bucket and prefix, and the S3 error code, when a page cannot be listed.
std::vector<S3Object> list_s3_objects(const std::string& url, unsigned page_size = 1000);

}  // namespace lidarscout::net
