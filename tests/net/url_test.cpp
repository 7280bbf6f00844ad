// net/url: URLs told from paths and parsed, credentials (userinfo, signed query strings)
// removed before display, credentials holding unencoded delimiters refused, origins compared,
// relative entries of a tile list resolved against the list's URL; s3 URLs among them; S3 keys
// normalised and refused when they leave their bucket or prefix, however they spell "..".
#include <gtest/gtest.h>

#include "net/url.hpp"

namespace lidarscout::net {
namespace {

TEST(Url, TellsUrlsFromPaths) {
    EXPECT_TRUE(is_url("http://host/a.laz"));
    EXPECT_TRUE(is_url("HTTPS://host/a.laz"));
    EXPECT_FALSE(is_url("/data/http://x"));
    EXPECT_FALSE(is_url("ftp://host/a.laz"));
    EXPECT_FALSE(is_url("tiles.txt"));
    EXPECT_EQ(url_scheme("HTTPS://h/x"), "https");
}

// s3 URLs are URLs too (read remotely, relative entries resolved within their bucket), the
// bucket their origin.
TEST(Url, S3UrlsAreUrlsWhoseOriginIsTheirBucket) {
    EXPECT_TRUE(is_url("s3://bucket/tiles/a.laz"));
    EXPECT_EQ(url_scheme("S3://bucket/k"), "s3");
    EXPECT_EQ(url_origin("s3://Bucket/k"), "s3://Bucket");  // (bucket names are case-sensitive)
    EXPECT_EQ(resolve_url("s3://bucket/lists/tiles.txt", "../t/a.laz"), "s3://bucket/t/a.laz");
    EXPECT_EQ(resolve_url("s3://bucket/lists/tiles.txt", "/t/a.laz"), "s3://bucket/t/a.laz");
}

TEST(Url, CredentialsAreRemoved) {
    EXPECT_EQ(redact_url("https://user:secret@host:8443/a.laz"), "https://host:8443/a.laz");
    EXPECT_EQ(redact_url("http://host/a@b.laz"), "http://host/a@b.laz");  // '@' in the path is kept
    EXPECT_EQ(redact_url("http://u:p%40x@host/a"), "http://host/a");
    EXPECT_EQ(redact_url("/local/user@x.laz"), "/local/user@x.laz");
}

TEST(Url, CredentialQueryParametersAreRedacted) {
    EXPECT_EQ(redact_url("https://b.s3.amazonaws.com/t.laz?X-Amz-Algorithm=AWS4-HMAC-SHA256&X-Amz-Credential=AKIA%2F1"
                         "&X-Amz-Date=20250101T000000Z&X-Amz-Security-Token=tok&X-Amz-Signature=abc123"),
              "https://b.s3.amazonaws.com/t.laz?X-Amz-Algorithm=AWS4-HMAC-SHA256&X-Amz-Credential=REDACTED"
              "&X-Amz-Date=20250101T000000Z&X-Amz-Security-Token=REDACTED&X-Amz-Signature=REDACTED");
    EXPECT_EQ(redact_url("https://a.blob.core.windows.net/c/t.laz?sv=2022-11-02&se=2030&sp=r&sig=SAS%3D"),
              "https://a.blob.core.windows.net/c/t.laz?sv=2022-11-02&se=2030&sp=r&sig=REDACTED");
    EXPECT_EQ(redact_url("https://storage.googleapis.com/b/t.laz?X-Goog-Signature=ff&x=1"),
              "https://storage.googleapis.com/b/t.laz?X-Goog-Signature=REDACTED&x=1");
    EXPECT_EQ(redact_url("http://u:p@h/t.laz?token=1&key=2&signature=3&access_token=4&page=5#access_token=6"),
              "http://h/t.laz?token=REDACTED&key=REDACTED&signature=REDACTED&access_token=REDACTED&page=5"
              "#access_token=REDACTED");
    EXPECT_EQ(redact_url("http://h/a.laz?flag&x="), "http://h/a.laz?flag&x=");
}

TEST(Url, CredentialsWithUnencodedDelimitersAreRefusedAndHidden) {
    for (const std::string url : {"http://u:pa#ss@host/a.laz", "http://u:pa?ss@host/a.laz", "http://u:pa/ss@host/a.laz",
                                  "http://u#x:pass@host/a.laz"}) {
        SCOPED_TRACE(url);
        EXPECT_NE(url_problem(url).find("percent-encode"), std::string::npos);
        EXPECT_EQ(redact_url(url), "http://host/a.laz");
    }
    EXPECT_EQ(redact_url("http://u:p#a@ss@host/a.laz"), "http://host/a.laz");
    EXPECT_EQ(url_problem("http://u:pa%23ss@host/a.laz"), "");
    EXPECT_EQ(url_problem("http://host:8080/a@b.laz?x=1"), "");
    EXPECT_EQ(url_problem("http://[::1]:8080/a.laz"), "");
    EXPECT_NE(url_problem("http://host:80x/a.laz").find("port \"80x\" is not a number"), std::string::npos);
    EXPECT_EQ(url_problem("/local/u:p#x@y"), "");
}

TEST(Url, PartsAndOrigins) {
    const auto p = parse_url("HTTPS://u:p@Host.Example:8443/a/b.laz?x=1#f");
    ASSERT_TRUE(p);
    EXPECT_EQ(p->scheme, "https");
    EXPECT_EQ(p->userinfo, "u:p");
    EXPECT_EQ(p->host, "Host.Example");
    EXPECT_EQ(p->port, "8443");
    EXPECT_EQ(p->path, "/a/b.laz");
    EXPECT_EQ(p->query, "x=1");
    EXPECT_EQ(p->fragment, "f");
    EXPECT_FALSE(parse_url("/a/b.laz"));
    EXPECT_EQ(url_origin("HTTPS://u:p@Host.Example:8443/a"), "https://host.example:8443");
    EXPECT_EQ(url_origin("http://h/a"), "http://h:80");
    EXPECT_EQ(url_origin("https://h"), "https://h:443");
    EXPECT_EQ(url_origin("http://[::1]:81/x"), "http://[::1]:81");
}

TEST(Url, RelativeReferencesResolveAgainstTheList) {
    const std::string base = "https://h:1/set/lists/tiles.txt?sig=1";
    EXPECT_EQ(resolve_url(base, "a.laz"), "https://h:1/set/lists/a.laz");
    EXPECT_EQ(resolve_url(base, "../tiles/a.laz"), "https://h:1/set/tiles/a.laz");
    EXPECT_EQ(resolve_url(base, "./x/../b.laz"), "https://h:1/set/lists/b.laz");
    EXPECT_EQ(resolve_url(base, "/root.laz"), "https://h:1/root.laz");
    EXPECT_EQ(resolve_url(base, "../../../../up.laz"), "https://h:1/up.laz");
    EXPECT_EQ(resolve_url(base, "//other/c.laz"), "https://other/c.laz");
    EXPECT_EQ(resolve_url(base, "http://else/d.laz"), "http://else/d.laz");
    EXPECT_EQ(resolve_url("http://h", "a.laz"), "http://h/a.laz");
}

// A plain reference resolved through the prefix equals resolve_url's answer for every base spelling, on base's
// origin (a catalog's items take this way); anything but http(s) has no prefix.
TEST(Url, PlainReferencesResolveThroughTheBasesPrefix) {
    for (const std::string base : {"https://h:1/set/lists/tiles.txt?sig=1", "http://h", "http://h/", "http://h?q=/a/b",
                                   "http://h/a/./b/../c/catalog.vpc#x", "https://u@h/a//b/search?bbox=1,2,3,4",
                                   "http://h/a/b/"}) {
        const auto prefix = plain_reference_prefix(base);
        ASSERT_TRUE(prefix) << base;
        for (const std::string ref : {"a.laz", "./a.laz", "x/y/z.laz", "./x/a b.laz", "a.laz?sig=2", "a#b"}) {
            const std::string plain = ref.starts_with("./") ? ref.substr(2) : ref;
            EXPECT_EQ(*prefix + plain, resolve_url(base, ref)) << base << " " << ref;
            EXPECT_EQ(url_origin(*prefix + plain), url_origin(base)) << base << " " << ref;
        }
    }
    EXPECT_FALSE(plain_reference_prefix("s3://bucket/a/catalog.vpc"));
    EXPECT_FALSE(plain_reference_prefix("/local/catalog.vpc"));
    EXPECT_FALSE(plain_reference_prefix("ftp://h/catalog.vpc"));
}

// The key as requested, or its refusal ("" key then).
std::string key_or_refusal(std::string_view key, std::string_view prefix = {}) {
    std::string refusal;
    const std::string normalised = normalise_s3_key(key, prefix, refusal);
    EXPECT_TRUE(refusal.empty() || normalised.empty()) << key;
    return refusal.empty() ? normalised : "refused: " + refusal;
}

TEST(Url, S3KeysAreNormalised) {
    EXPECT_EQ(key_or_refusal("tiles/a.laz"), "tiles/a.laz");
    EXPECT_EQ(key_or_refusal("tiles/./a.laz"), "tiles/a.laz");
    EXPECT_EQ(key_or_refusal("tiles/x/../a.laz"), "tiles/a.laz");
    EXPECT_EQ(key_or_refusal("./tiles/%2e/a.laz"), "tiles/a.laz");
    EXPECT_EQ(key_or_refusal("tiles/x/&#46;&#46;/a.laz"), "tiles/a.laz");
    EXPECT_EQ(key_or_refusal("tiles/x/.."), "tiles/");
    EXPECT_EQ(key_or_refusal("tiles//a...laz"), "tiles//a...laz");  // (empty segments and dots in names stay)
    EXPECT_EQ(key_or_refusal("a%20b&c.laz"), "a%20b&c.laz");         // (other escapes are the key's characters)
    EXPECT_EQ(key_or_refusal(""), "");
}

TEST(Url, S3KeysLeavingTheirBucketAreRefusedHoweverSpelled) {
    for (const char* key : {"../secret/t.laz", "a/../../secret/t.laz", "%2e%2e/secret/t.laz", "%2E%2e/t.laz",
                            "&#46;&#46;/secret/t.laz", "&#x2e;&#x2E;/t.laz", ".%2e/t.laz", "%252e%252e/t.laz",
                            "&amp;#46;&amp;#46;/t.laz", "..\\secret\\t.laz", "a/%2e%2e%2f%2e%2e%2ft.laz", "..",
                            "a/./../.."}) {
        EXPECT_NE(key_or_refusal(key).find("refused: leaves its bucket"), std::string::npos) << key;
    }
    EXPECT_EQ(key_or_refusal("/../t.laz"), "t.laz");  // (the empty segment after the bucket: still inside)
    EXPECT_EQ(key_or_refusal(std::string(1025, 'k')), "refused: is longer than S3's 1024 bytes (1025)");
    EXPECT_EQ(key_or_refusal(std::string(1024, 'k')).size(), 1024u);
}

TEST(Url, S3KeysLeavingThePrefixAreRefused) {
    EXPECT_EQ(key_or_refusal("tiles/a.laz", "tiles/"), "tiles/a.laz");
    EXPECT_EQ(key_or_refusal("tiles/x/../a.laz", "tiles/"), "tiles/a.laz");
    EXPECT_EQ(key_or_refusal("tiles/a.laz", "other/../tiles/"), "tiles/a.laz");
    for (const char* key : {"tiles/../secret/t.laz", "tiles/%2e%2e/secret/t.laz", "tiles/&#46;&#46;/t.laz",
                            "tiles/a%2f..%2f..%2fsecret.laz", "secret/t.laz"}) {
        EXPECT_NE(key_or_refusal(key, "tiles/").find("refused: leaves the prefix listed (\"tiles/\")"),
                  std::string::npos)
            << key;
    }
}

}  // namespace
}  // namespace lidarscout::net
