// net/origin_policy: a dataset's derived URLs keep its scheme and origin unless other origins
// are allowed; http after https is refused whatever is allowed; an s3 key may not leave its
// bucket however it spells "..".
#include <gtest/gtest.h>

#include "core/error.hpp"
#include "net/origin_policy.hpp"

namespace lidarscout::net {
namespace {

class OriginPolicy : public ::testing::Test {
protected:
    void TearDown() override { set_allowed_origins({}); }
};

TEST_F(OriginPolicy, DerivedUrlsKeepTheDatasetsOrigin) {
    const std::string base = "https://data.example/set/ept.json";
    EXPECT_EQ(derived_url_refusal(base, "https://DATA.example:443/set/ept-data/0-0-0-0.laz"), "");
    EXPECT_NE(derived_url_refusal(base, "https://other.example/x.laz").find("another origin"), std::string::npos);
    EXPECT_NE(derived_url_refusal(base, "https://data.example:8443/x.laz").find("another origin"), std::string::npos);
    EXPECT_NE(derived_url_refusal(base, "http://data.example/x.laz").find("downgrade from https to http"),
              std::string::npos);
    EXPECT_NE(derived_url_refusal("http://h/list.txt", "https://h/x.laz").find("another origin"), std::string::npos);
    // an s3 dataset's: its bucket
    EXPECT_EQ(derived_url_refusal("s3://b/set/list.txt", "s3://b/other/x.laz"), "");
    EXPECT_NE(derived_url_refusal("s3://b/list.txt", "s3://c/x.laz").find("another origin"), std::string::npos);
    EXPECT_NE(derived_url_refusal("s3://b/list.txt", "https://b/x.laz").find("another origin"), std::string::npos);
}

TEST_F(OriginPolicy, AnS3KeyLeavingItsBucketIsAnotherOrigin) {
    const std::string base = "s3://cat/catalog.json";
    EXPECT_EQ(derived_url_refusal(base, "s3://cat/items/../tiles/x.laz"), "");
    for (const char* href : {"s3://cat/../secret/x.laz", "s3://cat/%2e%2e/secret/x.laz",
                             "s3://cat/a/../../secret/x.laz", "s3://cat/&#46;&#46;/secret/x.laz",
                             "s3://cat/a?/../../secret/x.laz"}) {
        EXPECT_NE(derived_url_refusal(base, href).find("its key leaves its bucket"), std::string::npos)
            << href;
    }
    set_allowed_origins(parse_allowed_origins("*"));  // (other origins allowed: a key still stays in its bucket)
    EXPECT_NE(derived_url_refusal(base, "s3://cat/../secret/x.laz"), "");
}

TEST_F(OriginPolicy, AllowedOriginsMayBeUsedButNeverDowngraded) {
    set_allowed_origins(parse_allowed_origins("https://cdn.example,http://mirror:8080/any/path"));
    const std::string base = "https://data.example/list.txt";
    EXPECT_EQ(derived_url_refusal(base, "https://cdn.example/a.laz"), "");
    EXPECT_NE(derived_url_refusal(base, "https://elsewhere/a.laz"), "");
    EXPECT_NE(derived_url_refusal(base, "http://mirror:8080/a.laz").find("downgrade"), std::string::npos);
    EXPECT_EQ(derived_url_refusal("http://data.example/list.txt", "http://mirror:8080/a.laz"), "");
    set_allowed_origins(parse_allowed_origins("*"));
    EXPECT_EQ(derived_url_refusal(base, "https://elsewhere/a.laz"), "");
    EXPECT_NE(derived_url_refusal(base, "http://elsewhere/a.laz").find("downgrade"), std::string::npos);
}

TEST_F(OriginPolicy, ListsAreParsedStrictly) {
    EXPECT_TRUE(parse_allowed_origins("*").any);
    EXPECT_EQ(parse_allowed_origins("https://a,http://b:81").origins,
              (std::vector<std::string>{"https://a:443", "http://b:81"}));
    EXPECT_THROW(parse_allowed_origins("a.example"), Error);
    try {
        parse_allowed_origins("https://u:pa#ss@h");
        FAIL();
    } catch (const Error& e) {
        EXPECT_EQ(std::string(e.what()).find("pa#ss"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace lidarscout::net
