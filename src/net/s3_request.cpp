// s3:// URLs: their http(s) URLs, signing, requests and ListObjectsV2 listings.
#include "net/s3_request.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstdio>
#include <unordered_set>

#include "core/error.hpp"
#include "core/text.hpp"
#include "net/server_text.hpp"
#include "net/url.hpp"
#include "net/xml_text.hpp"

namespace lidarscout::net {

namespace {

// SHA-256 of an empty body: the payload hash of every GET (S3 wants it in x-amz-content-sha256).
constexpr const char* kEmptyPayload = "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855";

// RFC 3986 percent-encoding of everything but the unreserved characters (and '/' when kept).
std::string uri_encode(std::string_view s, bool keep_slash) {
    std::string out;
    for (const char ch : s) {
        const auto c = static_cast<unsigned char>(ch);
        if (std::isalnum(c) || c == '-' || c == '_' || c == '.' || c == '~' || (keep_slash && c == '/')) {
            out += ch;
        } else {
            char hex[4];
            std::snprintf(hex, sizeof hex, "%%%02X", c);
            out += hex;
        }
    }
    return out;
}

// "scheme://" and "host:port/path" of an endpoint URL.
std::pair<std::string, std::string> split_endpoint(const std::string& endpoint) {
    const auto colon = endpoint.find("://");
    return {endpoint.substr(0, colon + 3), endpoint.substr(colon + 3)};
}

std::string list_query(const std::string& prefix, const std::string& token, unsigned page_size) {
    std::string q;  // (parameters sorted by name)
    if (!token.empty()) q += "continuation-token=" + uri_encode(token, false) + "&";
    q += "list-type=2&max-keys=" + std::to_string(page_size);
    if (!prefix.empty()) q += "&prefix=" + uri_encode(prefix, false);
    return q;
}

// Why `bucket` cannot name a bucket ("" when it can): S3's names hold letters, digits, '.', '-'
// and (older ones) '_', and begin and end with a letter or digit, which keeps a virtual-hosted
// URL's host the one meant and a path-style URL's first segment a bucket (never "..").
std::string bucket_problem(const std::string& bucket) {
    const auto alnum = [](unsigned char c) { return std::isalnum(c) != 0; };
    const bool allowed = std::all_of(bucket.begin(), bucket.end(), [&](unsigned char c) {
        return alnum(c) || c == '.' || c == '-' || c == '_';
    });
    if (allowed && alnum(bucket.front()) && alnum(bucket.back())) return {};
    return "the bucket name \"" + server_text(bucket) + "\" is not one S3 allows";
}

// The normalised key of `where` (net/url.hpp) under `prefix`; throws Error naming `url` when
// the bucket's name is not one or the key is refused.
std::string checked_key(const std::string& url, const S3Location& where, std::string_view prefix) {
    if (const std::string problem = bucket_problem(where.bucket); !problem.empty()) {
        throw Error(url, std::nullopt, problem);
    }
    std::string refusal;
    std::string key = normalise_s3_key(where.key, prefix, refusal);
    if (!refusal.empty()) {
        throw Error(url, std::nullopt, "the key \"" + server_text(where.key) + "\" " + refusal);
    }
    return key;
}

std::uint64_t size_of(std::string_view text) {
    std::uint64_t size = 0;
    std::from_chars(text.data(), text.data() + text.size(), size);
    return size;
}

// One ListObjectsV2 listing, page after page, within its limits.
class Listing {
public:
    Listing(const std::string& url, const S3ObjectVisitor& take, const S3ListLimits& limits)
        : url_(url), take_(take), limits_(limits), config_(s3_config()) {
        const auto where = parse_s3_url(url);
        if (!where) throw Error(url, std::nullopt, "not an s3 URL (s3://bucket/prefix/)");
        bucket_ = where->bucket;
        prefix_ = checked_key(url, *where, {});
        context_ = " (bucket \"" + bucket_ + "\", prefix \"" + server_text(prefix_) + "\")";
    }

    std::uint64_t run() {
        std::string token;
        do {
            if (++pages_ > limits_.max_pages) fail("more than " + std::to_string(limits_.max_pages) + " pages");
            token = read_page(fetch_page(token));
        } while (!token.empty());
        return listed_;
    }

private:
    [[noreturn]] void fail(const std::string& cause) const {
        throw Error(url_, std::nullopt, "cannot be listed: " + cause + context_);
    }

    std::vector<std::uint8_t> fetch_page(const std::string& token) const {
        RangeRequest r{url_, {{0, limits_.max_page_bytes}}, {}};
        r.target = s3_http_url(config_, {bucket_, ""}, list_query(prefix_, token, limits_.page_size));
        r.signing = s3_signing(config_);
        r.whole = true;
        r.path_as_is = true;
        RangeReply reply = HttpClient::shared().fetch(std::move(r));
        if (!reply.error.empty()) fail(reply.error + " (page " + std::to_string(pages_) + ")");
        return std::move(reply.parts.at(0));
    }

    // Takes the page's objects; returns its continuation token ("" for the last page).
    std::string read_page(const std::vector<std::uint8_t>& body) {
        const std::string_view xml(reinterpret_cast<const char*>(body.data()), body.size());
        std::uint64_t keys = 0;
        for_each_xml_element(xml, "Contents", [&](std::string_view contents) {
            if (++keys > limits_.page_size) {
                fail("page " + std::to_string(pages_) + " holds more than the " + std::to_string(limits_.page_size) +
                     " keys asked for");
            }
            take_object(contents);
            return true;
        });
        if (xml_text(xml, "IsTruncated") != "true") return {};
        std::string token = xml_text(xml, "NextContinuationToken");
        if (token.empty()) fail("a truncated ListObjectsV2 page without NextContinuationToken");
        if (token.size() > limits_.max_token) {
            fail("a continuation token of " + std::to_string(token.size()) + " bytes (at most " +
                 std::to_string(limits_.max_token) + ")");
        }
        if (!tokens_.insert(token).second) {
            fail("the server gave a continuation token it gave before (page " + std::to_string(pages_) + ")");
        }
        return token;
    }

    void take_object(std::string_view contents) {
        std::string key = xml_text(contents, "Key");
        std::string refusal;
        std::string normalised = normalise_s3_key(key, prefix_, refusal);
        if (!refusal.empty()) fail("the key \"" + server_text(key) + "\" " + refusal);
        if (listed_ > 0 && key <= previous_) {
            fail("the key \"" + server_text(key) + "\" does not come after \"" + server_text(previous_) +
                 "\" (keys are listed once each, in order)");
        }
        if (++listed_ > limits_.max_keys) fail("more than " + std::to_string(limits_.max_keys) + " keys");
        previous_ = std::move(key);
        const std::size_t bytes = normalised.size();
        if (!take_({std::move(normalised), size_of(xml_text(contents, "Size"))})) return;
        kept_bytes_ += bytes;
        if (kept_bytes_ > limits_.max_kept_bytes) {
            fail("the keys listed take more than " + std::to_string(limits_.max_kept_bytes >> 20) + " MiB");
        }
    }

    const std::string& url_;
    const S3ObjectVisitor& take_;
    const S3ListLimits& limits_;
    const S3Config config_;
    std::string bucket_, prefix_, context_;
    std::string previous_;  // the last key listed, as the server wrote it
    std::unordered_set<std::string> tokens_;
    std::uint64_t pages_ = 0, listed_ = 0, kept_bytes_ = 0;
};

}  // namespace

bool is_s3_url(std::string_view url) { return url.size() >= 5 && ascii_lower(url.substr(0, 5)) == "s3://"; }

std::optional<S3Location> parse_s3_url(std::string_view url) {
    if (!is_s3_url(url)) return std::nullopt;
    const std::string_view rest = url.substr(5);
    const auto slash = rest.find('/');
    S3Location where{std::string(rest.substr(0, slash)), {}};
    if (slash != std::string_view::npos) where.key = std::string(rest.substr(slash + 1));
    if (where.bucket.empty()) return std::nullopt;
    return where;
}

std::string s3_http_url(const S3Config& config, const S3Location& where, const std::string& query) {
    const std::string key = "/" + uri_encode(where.key, true);  // (a bucket's own: "/" virtual, "" path-style)
    const std::string endpoint =
        config.endpoint.empty() ? "https://s3." + config.region + ".amazonaws.com" : config.endpoint;
    std::string url;
    if (config.path_style(where.bucket)) {
        url = endpoint + "/" + uri_encode(where.bucket, false) + (where.key.empty() ? "" : key);
    } else {
        const auto [scheme, host] = split_endpoint(endpoint);
        url = scheme + where.bucket + "." + host + key;
    }
    return query.empty() ? url : url + "?" + query;
}

RequestSigning s3_signing(const S3Config& config) {
    RequestSigning s;
    if (config.requester_pays) s.headers.push_back("x-amz-request-payer: requester");
    if (config.anonymous()) return s;
    s.aws_sigv4 = "aws:amz:" + config.region + ":s3";
    s.access_key = config.access_key;
    s.secret = config.secret_key;
    s.headers.push_back(std::string("x-amz-content-sha256: ") + kEmptyPayload);
    if (!config.session_token.empty()) s.headers.push_back("x-amz-security-token: " + config.session_token);
    return s;
}

RangeRequest remote_request(const std::string& url, std::vector<ByteRange> ranges, std::string validator) {
    RangeRequest r{url, std::move(ranges), std::move(validator)};
    if (!is_s3_url(url)) return r;
    auto where = parse_s3_url(url);
    if (where) where->key = checked_key(url, *where, {});
    if (!where || where->key.empty() || where->key.back() == '/') {
        throw Error(url, std::nullopt, "an s3 URL of a file needs a bucket and a key (s3://bucket/key)");
    }
    const S3Config config = s3_config();
    r.target = s3_http_url(config, *where, {});
    r.signing = s3_signing(config);
    r.path_as_is = true;
    r.one_range = true;  // GetObject answers several ranges with the whole object
    return r;
}

std::string s3_error_context(std::string_view url) {
    const auto where = parse_s3_url(url);
    if (!where) return {};
    return " (bucket \"" + where->bucket + "\", key \"" + where->key + "\")";
}

std::uint64_t for_each_s3_object(const std::string& url, const S3ObjectVisitor& take, const S3ListLimits& limits) {
    return Listing(url, take, limits).run();
}

std::vector<S3Object> list_s3_objects(const std::string& url, const S3ListLimits& limits) {
    std::vector<S3Object> out;
    for_each_s3_object(url, [&out](S3Object&& o) { return out.push_back(std::move(o)), true; }, limits);
    return out;
}

}  // namespace lidarscout::net
