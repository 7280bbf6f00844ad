// dataset/source_identity: URLs that name one resource have one normal form (case of scheme and
// host, default ports, credentials, fragments, percent-encodings, dot segments), URLs that name
// others keep theirs (paths' case, other ports, queries, an encoded '/', an s3 key's literal '%');
// local names of one file have one identity, a virtual tile's shift makes another.
#include "dataset/source_identity.hpp"

#include <gtest/gtest.h>

#include <cctype>
#include <filesystem>
#include <fstream>
#include <random>
#include <set>

#include "temp_dir_fixture.hpp"

namespace lidarscout::dataset {
namespace {

namespace fs = std::filesystem;

TEST(NormalisedUrl, NamesOfOneResourceMeet) {
    const std::string plain = "http://example.com/d/t.laz";
    for (const char* same : {"HTTP://Example.COM/d/t.laz", "http://example.com:80/d/t.laz",
                             "http://user:secret@example.com/d/t.laz", "http://example.com/d/t.laz#part",
                             "http://example.com/d/./x/../t.laz", "http://example.com/../d/t.laz",
                             "http://example.com/%64/%74%2E%6c%61%7A", "http://example.com/d/x/%2E%2E/t.laz"}) {
        EXPECT_EQ(normalised_url(same), plain) << same;
    }
    EXPECT_EQ(normalised_url("https://example.com:443/a"), "https://example.com/a");
    EXPECT_EQ(normalised_url("http://example.com"), "http://example.com/");
    EXPECT_EQ(normalised_url("http://example.com/a%2fb?x=%7e%2a"), "http://example.com/a%2Fb?x=~%2A");
    EXPECT_EQ(normalised_url("s3://bucket/d/../t.laz"), "s3://bucket/t.laz");
    EXPECT_EQ(normalised_url("s3://bucket/d/%2e%2e/./t.laz"), "s3://bucket/t.laz") << "the key as requested";
}

TEST(NormalisedUrl, NamesOfOtherResourcesStayApart) {
    const std::string plain = normalised_url("http://example.com/d/t.laz");
    for (const char* other : {"http://example.com/D/t.laz", "https://example.com/d/t.laz",
                              "http://example.com:8080/d/t.laz", "http://example.com/d/t.laz?v=2",
                              "http://example.com//d/t.laz", "http://example.com/d%2Ft.laz",
                              "http://example.org/d/t.laz"}) {
        EXPECT_NE(normalised_url(other), plain) << other;
    }
    EXPECT_NE(normalised_url("s3://Bucket/t.laz"), normalised_url("s3://bucket/t.laz")) << "a bucket as written";
    EXPECT_NE(normalised_url("s3://bucket/%41.laz"), normalised_url("s3://bucket/A.laz")) << "an s3 key is literal";
    EXPECT_EQ(normalised_url("tiles/t.laz"), "tiles/t.laz") << "not a URL: as it is";
}

TEST(NormalisedUrl, AUrlInItsNormalFormIsItsOwnAndItsVariantsMeetIt) {
    for (const std::string normal : {"http://example.com/d/t.laz", "https://example.com/a",
                                     "http://127.0.0.1:8080/t/x.laz", "http://example.com/d/t.laz?v=2&x=y",
                                     "http://a-b.example.com/d.e/t.laz"}) {
        EXPECT_EQ(normalised_url(normal), normal);
        const std::size_t host = normal.find("://") + 3;
        std::string upper = normal;  // its scheme and host in capitals, a dot segment: not normal as written
        for (std::size_t i = 0; i < normal.find('/', host); ++i) upper[i] = static_cast<char>(std::toupper(upper[i]));
        upper.insert(normal.find('/', host), "/x/..");
        EXPECT_EQ(normalised_url(upper), normal) << upper;
    }
    EXPECT_EQ(normalised_url("http://example.com:080/a"), "http://example.com:080/a") << "another port as written";
    EXPECT_EQ(normalised_url("http://example.com/a/."), "http://example.com/a/");
    for (const std::string normal : {"http://h/a/", "http://h/", "http://h/.a/..b/c.", "http://h/a?x=//./../"}) {
        EXPECT_EQ(normalised_url(normal), normal);
    }
    EXPECT_EQ(normalised_url("HTTP://h/a//"), "http://h/a//") << "an empty segment kept";
    EXPECT_NE(normalised_url("http://h/a//b"), "http://h/a/b");
    EXPECT_EQ(normalised_url("http://h/a/.."), "http://h/");
    EXPECT_EQ(normalised_url("http://h/./a"), "http://h/a");
    EXPECT_EQ(normalised_url("http://example.com/a?q=%7e"), "http://example.com/a?q=~");
}

class SourceIdentity : public test::TempDirTest {};

TEST_F(SourceIdentity, LocalNamesOfOneFileMeetAndShiftsPartThem) {
    std::ofstream(dir / "t.laz") << "x";
    std::ofstream(dir / "u.laz") << "x";
    fs::create_directories(dir / "sub");
    fs::create_symlink(dir / "t.laz", dir / "link.laz");
    fs::create_hard_link(dir / "t.laz", dir / "hard.laz");
    const std::string t = source_identity({path("t.laz"), std::nullopt, "", nullptr});
    EXPECT_EQ(t.rfind("file:", 0), 0u) << t;
    for (const auto& same : {dir / "sub/../t.laz", dir / "./t.laz", dir / "link.laz", dir / "hard.laz"}) {
        EXPECT_EQ(source_identity({same.string(), std::nullopt, "", nullptr}), t) << same;
    }
    EXPECT_NE(source_identity({path("u.laz"), std::nullopt, "", nullptr}), t) << "a copy is another file";
    const std::string shifted = source_identity({path("t.laz"), std::array<double, 2>{1000, 0}, "v1.laz", nullptr});
    EXPECT_NE(shifted, t);
    EXPECT_EQ(source_identity({path("link.laz"), std::array<double, 2>{1000, 0}, "other name", nullptr}), shifted);
    EXPECT_NE(source_identity({path("t.laz"), std::array<double, 2>{2000, 0}, "v2.laz", nullptr}), shifted);
    // a file that does not exist: by its absolute, lexically normal path
    EXPECT_EQ(source_identity({path("missing.laz"), std::nullopt, "", nullptr}),
              source_identity({(dir / "sub/../missing.laz").string(), std::nullopt, "", nullptr}));
}

// URLs in their normal form and URLs in another spelling of them meet (the first are compared as written, the
// others once normalised), whichever comes first; a local file, a shifted URL and another URL stay apart.
TEST_F(SourceIdentity, DuplicatesAreDroppedWhetherOrNotAUrlIsWrittenInItsNormalForm) {
    std::ofstream(dir / "t.laz") << "x";
    FoundSources found;
    for (const std::string p : std::vector<std::string>{"http://example.com/d/t.laz", "HTTP://Example.COM/d/./t.laz",
                                                        "http://example.com:80/d/x/../t.laz",
                                                        "http://example.com/d/u.laz", path("t.laz"),
                                                        "HTTP://EXAMPLE.COM/d/u.laz"}) {
        found.sources.push_back({p, std::nullopt, "", nullptr});
    }
    found.sources.push_back({"http://example.com/d/t.laz", std::array<double, 2>{1000, 0}, "v.laz", nullptr});
    drop_duplicate_sources(found);
    std::vector<std::string> kept;
    for (const auto& s : found.sources) kept.push_back(s.path);
    EXPECT_EQ(kept, (std::vector<std::string>{"http://example.com/d/t.laz", "http://example.com/d/u.laz",
                                              path("t.laz"), "http://example.com/d/t.laz"}));
    const auto warnings = found.warnings.messages();
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_NE(warnings[0].find("3 inputs name tiles already named"), std::string::npos) << warnings[0];

    FoundSources reversed;  // the other spelling first
    for (const std::string p : {"HTTP://Example.COM/d/./t.laz", "http://example.com/d/t.laz"}) {
        reversed.sources.push_back({p, std::nullopt, "", nullptr});
    }
    drop_duplicate_sources(reversed);
    ASSERT_EQ(reversed.sources.size(), 1u);
    EXPECT_EQ(reversed.sources[0].path, "HTTP://Example.COM/d/./t.laz");
}

// Thousands of sources (several of the blocks hashed at once), a third of them repeats in another spelling or
// the same: the first of each tile kept, in order, as a set of normal forms keeps them; the count in the warning.
TEST(DropDuplicateSources, ThousandsKeepTheFirstOfEachTileInOrder) {
    FoundSources found;
    std::mt19937 random(7);
    for (int i = 0; i < 9000; ++i) {
        const int tile = static_cast<int>(random() % 6000);
        const std::string name = "/d/t" + std::to_string(tile) + ".laz";
        found.sources.push_back({(random() % 2 ? "HTTP://Example.COM" : "http://example.com") + name, std::nullopt,
                                 "", nullptr});
    }
    std::vector<std::string> expected;
    std::set<std::string> seen;
    for (const auto& s : found.sources) {
        if (seen.insert(normalised_url(s.path)).second) expected.push_back(s.path);
    }
    ASSERT_LT(expected.size(), 7000u);
    drop_duplicate_sources(found);
    std::vector<std::string> kept;
    for (const auto& s : found.sources) kept.push_back(s.path);
    EXPECT_EQ(kept, expected);
    const auto warnings = found.warnings.messages();
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_NE(warnings[0].find(std::to_string(9000 - expected.size()) + " inputs name tiles already named"),
              std::string::npos) << warnings[0];
}

}  // namespace
}  // namespace lidarscout::dataset
