// net/url: URLs told from paths, credentials removed before display, relative entries of a
// tile list resolved against the list's URL.
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

TEST(Url, CredentialsAreRemoved) {
    EXPECT_EQ(redact_url("https://user:secret@host:8443/a.laz"), "https://host:8443/a.laz");
    EXPECT_EQ(redact_url("http://host/a@b.laz"), "http://host/a@b.laz");  // '@' in the path is kept
    EXPECT_EQ(redact_url("http://u:p%40x@host/a"), "http://host/a");
    EXPECT_EQ(redact_url("/local/user@x.laz"), "/local/user@x.laz");
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

}  // namespace
}  // namespace lidarscout::net
