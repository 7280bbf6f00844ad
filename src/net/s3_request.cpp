// s3:// URLs: their http(s) URLs, signing, requests and ListObjectsV2 listings.
#include "net/s3_request.hpp"

#include <cctype>
#include <cstdio>

#include "core/error.hpp"
#include "core/text.hpp"
#include "net/xml_text.hpp"

namespace lidarscout::net {

namespace {

// SHA-256 of an empty body: the payload hash of every GET (S3 wants it in x-amz-content-sha256).
constexpr const char* kEmptyPayload = "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855";
// The most bytes of one ListObjectsV2 page accepted (1,000 keys take about 300 KiB).
constexpr std::uint64_t kMaxListing = 64ull << 20;

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

struct ListPage {
    std::vector<S3Object> objects;
    std::string next_token;  // "" when the listing is complete
};

ListPage parse_list_page(std::string_view xml) {
    ListPage page;
    for (const auto contents : xml_elements(xml, "Contents")) {
        S3Object o{xml_text(contents, "Key"), 0};
        try {
            o.size = std::stoull(xml_text(contents, "Size"));
        } catch (const std::exception&) {
            o.size = 0;
        }
        page.objects.push_back(std::move(o));
    }
    if (xml_text(xml, "IsTruncated") == "true") {
        page.next_token = xml_text(xml, "NextContinuationToken");
        if (page.next_token.empty()) throw Error("a truncated ListObjectsV2 page without NextContinuationToken");
    }
    return page;
}

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
    const auto where = parse_s3_url(url);
    if (!where || where->key.empty() || where->key.back() == '/') {
        throw Error(url, std::nullopt, "an s3 URL of a file needs a bucket and a key (s3://bucket/key)");
    }
    const S3Config config = s3_config();
    r.target = s3_http_url(config, *where, {});
    r.signing = s3_signing(config);
    return r;
}

std::string s3_error_context(std::string_view url) {
    const auto where = parse_s3_url(url);
    if (!where) return {};
    return " (bucket \"" + where->bucket + "\", key \"" + where->key + "\")";
}

std::vector<S3Object> list_s3_objects(const std::string& url, unsigned page_size) {
    const auto where = parse_s3_url(url);
    if (!where) throw Error(url, std::nullopt, "not an s3 URL (s3://bucket/prefix/)");
    const S3Config config = s3_config();
    std::vector<S3Object> out;
    std::string token;
    do {
        RangeRequest r{url, {{0, kMaxListing}}, {}};
        r.target = s3_http_url(config, {where->bucket, ""}, list_query(where->key, token, page_size));
        r.signing = s3_signing(config);
        r.whole = true;
        RangeReply reply = HttpClient::shared().fetch(std::move(r));
        const std::string context = " (bucket \"" + where->bucket + "\", prefix \"" + where->key + "\")";
        if (!reply.error.empty()) throw Error(url, std::nullopt, "cannot be listed: " + reply.error + context);
        const auto& body = reply.parts.at(0);
        ListPage page;
        try {
            page = parse_list_page(std::string_view(reinterpret_cast<const char*>(body.data()), body.size()));
        } catch (const Error& e) {
            throw Error(url, std::nullopt, e.cause() + context);
        }
        out.insert(out.end(), page.objects.begin(), page.objects.end());
        token = std::move(page.next_token);
    } while (!token.empty());
    return out;
}

}  // namespace lidarscout::net
