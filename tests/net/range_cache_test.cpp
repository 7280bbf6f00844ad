// net/range_cache: stored replies come back for the same URL, validator and ranges only;
// damaged entries (flipped bytes, truncated, replaced by a huge file) are dropped with a
// diagnostic naming them, without reading a file larger than the entry can be; the folder
// stays under its limit, least recently used first; a store returns before its entry is written (by the
// cache's thread), and what is queued is found as if it were; entries of any size come back whole and the
// files hold no padding; small entries go into a pack and its index (one file each for hundreds), come back
// from a new cache, a damaged record is dropped alone, a torn index loses its last record only, and packs are
// evicted whole under the limit (an index whose pack is gone too).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <thread>

#include "net/range_cache.hpp"

namespace lidarscout::net {
namespace {

namespace fs = std::filesystem;

class RangeCacheTest : public ::testing::Test {
protected:
    fs::path dir = fs::temp_directory_path() / ("lidarscout_range_cache_" + std::to_string(::getpid()));
    void TearDown() override { fs::remove_all(dir); }

    static RangeReply reply_of(std::vector<std::vector<std::uint8_t>> parts) {
        RangeReply r;
        r.parts = std::move(parts);
        return r;
    }
    static std::uint64_t folder_bytes(const fs::path& d) {
        std::uint64_t total = 0;
        for (const auto& e : fs::recursive_directory_iterator(d)) {
            if (e.is_regular_file()) total += e.file_size();
        }
        return total;
    }
};

TEST_F(RangeCacheTest, RepliesComeBackForTheSameRequestOnly) {
    RangeCache cache({dir, 1 << 20});
    const RangeRequest request{"http://h/a.laz", {{0, 3}, {100, 2}}, "\"v1\""};
    cache.store(request, reply_of({{1, 2, 3}, {9, 8}}));
    const auto found = cache.find(request);
    ASSERT_TRUE(found);
    EXPECT_EQ(*found, (std::vector<std::vector<std::uint8_t>>{{1, 2, 3}, {9, 8}}));
    EXPECT_FALSE(cache.find({"http://h/a.laz", {{0, 3}, {100, 2}}, "\"v2\""}));  // another version
    EXPECT_FALSE(cache.find({"http://h/a.laz", {{0, 3}}, "\"v1\""}));            // other ranges
    EXPECT_FALSE(cache.find({"http://h/b.laz", {{0, 3}, {100, 2}}, "\"v1\""}));  // another file
    EXPECT_EQ(cache.hits(), 1u);

    const RangeRequest unpinned{"http://h/a.laz", {{0, 3}}, ""};  // no validator: never cached
    cache.store(unpinned, reply_of({{1, 2, 3}}));
    EXPECT_FALSE(cache.find(unpinned));
}

TEST_F(RangeCacheTest, DamagedEntriesAreDropped) {
    RangeCache cache({dir, 1 << 20, 0});  // (entry files: no packs)
    const RangeRequest request{"http://h/a.laz", {{0, 4}}, "\"v1\""};
    cache.store(request, reply_of({{1, 2, 3, 4}}));
    cache.flush();
    for (const auto& e : fs::recursive_directory_iterator(dir)) {
        if (e.is_regular_file()) fs::resize_file(e.path(), e.file_size() - 1);
    }
    EXPECT_FALSE(cache.find(request));
    EXPECT_EQ(folder_bytes(dir), 0u);
}

TEST_F(RangeCacheTest, FlippedBytesFailTheChecksumAndAreDroppedWithADiagnostic) {
    RangeCache cache({dir, 1 << 20, 0});  // (entry files: no packs)
    const RangeRequest request{"http://u:pw@h/a.laz?sig=s3cret", {{0, 4000}}, "\"v1\""};
    cache.store(request, reply_of({std::vector<std::uint8_t>(4000, 7)}));
    cache.flush();
    fs::path entry;
    for (const auto& e : fs::recursive_directory_iterator(dir)) {
        if (e.is_regular_file()) entry = e.path();
    }
    ASSERT_FALSE(entry.empty());
    {
        std::fstream f(entry, std::ios::in | std::ios::out | std::ios::binary);
        f.seekp(2000);
        f.write("XXXXXXXXXX", 10);  // the same size, other bytes
    }
    EXPECT_FALSE(cache.find(request));
    EXPECT_FALSE(fs::exists(entry));
    const auto diagnostics = cache.take_diagnostics();
    ASSERT_EQ(diagnostics.size(), 1u);
    EXPECT_EQ(diagnostics[0].file, entry.string());
    const std::string& message = diagnostics[0].message;
    EXPECT_NE(message.find("does not match its SHA-256"), std::string::npos) << message;
    EXPECT_NE(message.find("http://h/a.laz?sig=REDACTED, bytes 0-3999"), std::string::npos) << message;
    EXPECT_EQ(message.find("s3cret"), std::string::npos) << message;
    EXPECT_TRUE(cache.take_diagnostics().empty());
    cache.store(request, reply_of({std::vector<std::uint8_t>(4000, 7)}));  // fetched again, stored again
    EXPECT_TRUE(cache.find(request));
}

TEST_F(RangeCacheTest, AnEntryLargerThanItsRangesIsDroppedUnread) {
    RangeCache cache({dir, 1ull << 40, 0});  // (entry files: no packs)
    const RangeRequest request{"http://h/a.laz", {{0, 2048}}, "\"v1\""};
    cache.store(request, reply_of({std::vector<std::uint8_t>(2048, 1)}));
    cache.flush();
    for (const auto& e : fs::recursive_directory_iterator(dir)) {
        if (e.is_regular_file()) fs::resize_file(e.path(), 1ull << 30);  // 1 GiB (sparse) in its place
    }
    EXPECT_FALSE(cache.find(request));
    const auto diagnostics = cache.take_diagnostics();
    ASSERT_EQ(diagnostics.size(), 1u);
    EXPECT_NE(diagnostics[0].message.find("its size, 1073741824 bytes, is more than its ranges can hold"),
              std::string::npos)
        << diagnostics[0].message;
    EXPECT_EQ(folder_bytes(dir), 0u);
}

TEST_F(RangeCacheTest, FolderStaysUnderItsLimitDroppingTheLeastRecentlyUsed) {
    RangeCache cache({dir, 50'000});
    const std::vector<std::uint8_t> block(10'000, 7);
    auto request = [](int i) { return RangeRequest{"http://h/" + std::to_string(i), {{0, 10'000}}, "e"}; };
    for (int i = 0; i < 4; ++i) cache.store(request(i), reply_of({block}));
    cache.flush();
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    ASSERT_TRUE(cache.find(request(0)));  // used again: now the most recent
    for (int i = 4; i < 7; ++i) cache.store(request(i), reply_of({block}));  // three over: 1, 2, 3 dropped
    cache.flush();
    EXPECT_TRUE(cache.find(request(0)));
    EXPECT_FALSE(cache.find(request(1)));
    EXPECT_FALSE(cache.find(request(3)));
    for (int i = 7; i < 20; ++i) cache.store(request(i), reply_of({block}));
    cache.flush();
    EXPECT_LE(folder_bytes(dir), 50'000u);
    EXPECT_TRUE(cache.find(request(19)));
}

TEST_F(RangeCacheTest, QueuedRepliesAreFoundAndWrittenOnceFlushedOrDestroyed) {
    const RangeRequest request{"http://h/a.laz", {{0, 3}}, "\"v1\""};
    {
        RangeCache cache({dir, 1ull << 30});
        cache.store(request, reply_of({{1, 2, 3}}));
        const auto found = cache.find(request);  // written or still queued: found either way
        ASSERT_TRUE(found);
        EXPECT_EQ((*found)[0], (std::vector<std::uint8_t>{1, 2, 3}));
        // a reply larger than the queue may hold is written when it is alone in it
        const RangeRequest large{"http://h/large.laz", {{0, RangeCache::kMaxQueuedBytes + 1}}, "\"v1\""};
        cache.flush();
        cache.store(large, reply_of({std::vector<std::uint8_t>(RangeCache::kMaxQueuedBytes + 1, 5)}));
        cache.store(request, reply_of({{1, 2, 3}}));  // (behind it, the queue full: not queued again)
    }  // the destructor writes what is queued
    RangeCache again({dir, 1ull << 30});
    EXPECT_TRUE(again.find(request));
    const auto large = again.find({"http://h/large.laz", {{0, RangeCache::kMaxQueuedBytes + 1}}, "\"v1\""});
    ASSERT_TRUE(large);
    EXPECT_EQ((*large)[0].size(), RangeCache::kMaxQueuedBytes + 1);
    EXPECT_EQ(again.hits(), 2u);
}

// Entries go through a staging buffer (around the page cache where the file system allows: its last block padded,
// the file cut to its size): every size about the buffer's and the alignment's comes back whole, each file exactly
// as long as its entry.
TEST_F(RangeCacheTest, EntriesOfEverySizeComeBackWholeAndNoLongerThanThemselves) {
    RangeCache cache({dir, 1ull << 30, 0});  // (entry files: no packs)
    const std::size_t staging = RangeCache::kStagingBytes, align = RangeCache::kDirectAlignment;
    const std::vector<std::size_t> sizes{0, 1, align - 1, align, staging - 93, staging, 2 * staging + align + 7};
    std::vector<RangeRequest> requests;
    std::vector<std::vector<std::uint8_t>> contents;
    std::uint64_t expected_bytes = 0;
    for (std::size_t k = 0; k < sizes.size(); ++k) {
        std::vector<std::uint8_t> bytes(sizes[k]);
        for (std::size_t i = 0; i < bytes.size(); ++i) bytes[i] = static_cast<std::uint8_t>(i * 131 + k * 7 + i / 251);
        requests.push_back({"http://h/" + std::to_string(k) + ".laz", {{0, sizes[k] + 1}, {sizes[k] + 9, 1}}, "\"v\""});
        cache.store(requests.back(), reply_of({bytes, {static_cast<std::uint8_t>(k)}}));
        cache.flush();
        expected_bytes += 8 + 8 + 2 * (8 + 64) + sizes[k] + 1;  // magic, count, each part's length and SHA-256
        contents.push_back(std::move(bytes));
    }
    EXPECT_EQ(folder_bytes(dir), expected_bytes);
    RangeCache again({dir, 1ull << 30, 0});
    for (std::size_t k = 0; k < sizes.size(); ++k) {
        const auto found = again.find(requests[k]);
        ASSERT_TRUE(found) << sizes[k];
        ASSERT_EQ(found->size(), 2u);
        EXPECT_EQ((*found)[0], contents[k]) << sizes[k];
        EXPECT_EQ((*found)[1], std::vector<std::uint8_t>{static_cast<std::uint8_t>(k)});
    }
    EXPECT_TRUE(again.take_diagnostics().empty());
}

// Small entries: one pack and one index for all of them, each record its key and entry, each index record 80
// bytes; a new cache (another process) finds them all from the index.
TEST_F(RangeCacheTest, SmallEntriesGoIntoOnePackAndComeBackFromItsIndex) {
    const auto request = [](int i) { return RangeRequest{"http://h/t" + std::to_string(i) + ".laz", {{0, 300}}, "e"}; };
    const auto bytes = [](int i) { return std::vector<std::uint8_t>(100 + i % 200, static_cast<std::uint8_t>(i)); };
    std::uint64_t expected_pack = 0;
    {
        RangeCache cache({dir, 1ull << 30});
        for (int i = 0; i < 500; ++i) {
            cache.store(request(i), reply_of({bytes(i)}));
            expected_pack += 64 + 8 + 8 + 8 + 64 + bytes(i).size();  // key, magic, count, length, SHA-256, bytes
        }
        cache.flush();
        EXPECT_TRUE(cache.find(request(7)));
    }
    std::vector<fs::path> files;
    for (const auto& e : fs::recursive_directory_iterator(dir)) {
        if (e.is_regular_file()) files.push_back(e.path());
    }
    ASSERT_EQ(files.size(), 2u) << "one pack and its index, no entry files";
    std::sort(files.begin(), files.end());  // NAME.index, NAME.pack
    EXPECT_EQ(files[0].extension(), ".index");
    EXPECT_EQ(fs::file_size(files[0]), 500u * 80);
    EXPECT_EQ(fs::file_size(files[1]), expected_pack);
    RangeCache again({dir, 1ull << 30});
    for (int i = 0; i < 500; ++i) {
        const auto found = again.find(request(i));
        ASSERT_TRUE(found) << i;
        EXPECT_EQ(*found, std::vector<std::vector<std::uint8_t>>{bytes(i)});
    }
    EXPECT_FALSE(again.find({"http://h/t1.laz", {{0, 300}}, "other"}));
    EXPECT_EQ(again.hits(), 500u);
    EXPECT_TRUE(again.take_diagnostics().empty());
}

// A flipped byte in one record: that record dropped (a diagnostic naming the pack, the byte and the redacted
// URL), its neighbours still found; fetched and stored again it is found. A torn index: its last record lost.
TEST_F(RangeCacheTest, ADamagedRecordIsDroppedAloneAndATornIndexLosesItsLastRecord) {
    const auto request = [](int i) {
        return RangeRequest{"http://u:pw@h/t" + std::to_string(i) + ".laz?sig=s3cret", {{0, 1000}}, "e"};
    };
    const std::vector<std::uint8_t> block(1000, 9);
    {
        RangeCache cache({dir, 1ull << 30});
        for (int i = 0; i < 3; ++i) cache.store(request(i), reply_of({block}));
    }
    fs::path pack, index;
    for (const auto& e : fs::recursive_directory_iterator(dir)) {
        if (e.path().extension() == ".pack") pack = e.path();
        if (e.path().extension() == ".index") index = e.path();
    }
    ASSERT_FALSE(pack.empty());
    const std::uint64_t record = 64 + 8 + 8 + 8 + 64 + 1000;
    ASSERT_EQ(fs::file_size(pack), 3 * record);
    {
        std::fstream f(pack, std::ios::in | std::ios::out | std::ios::binary);
        f.seekp(static_cast<std::streamoff>(record + 700));  // in the second record's bytes
        f.write("X", 1);
    }
    RangeCache cache({dir, 1ull << 30});
    EXPECT_TRUE(cache.find(request(0)));
    EXPECT_FALSE(cache.find(request(1)));
    EXPECT_TRUE(cache.find(request(2)));
    const auto diagnostics = cache.take_diagnostics();
    ASSERT_EQ(diagnostics.size(), 1u);
    EXPECT_EQ(diagnostics[0].file, pack.string());
    const std::string& message = diagnostics[0].message;
    EXPECT_NE(message.find("at byte " + std::to_string(record) + " of"), std::string::npos) << message;
    EXPECT_NE(message.find("does not match its SHA-256"), std::string::npos) << message;
    EXPECT_NE(message.find("http://h/t1.laz?sig=REDACTED, bytes 0-999"), std::string::npos) << message;
    EXPECT_EQ(message.find("s3cret"), std::string::npos) << message;
    EXPECT_FALSE(cache.find(request(1))) << "forgotten, not read again";
    EXPECT_TRUE(cache.take_diagnostics().empty());
    cache.store(request(1), reply_of({block}));
    cache.flush();
    EXPECT_TRUE(cache.find(request(1)));

    fs::resize_file(index, 2 * 80 + 30);  // the third record torn
    RangeCache torn({dir, 1ull << 30});
    EXPECT_TRUE(torn.find(request(0)));
    EXPECT_FALSE(torn.find(request(2)));
    EXPECT_TRUE(torn.take_diagnostics().empty());
}

// Under a small limit packs are sealed small and evicted whole, least recently used first, their indexes with
// them: the folder stays under the limit and the latest entries are found.
TEST_F(RangeCacheTest, PacksAreEvictedWholeUnderTheLimit) {
    fs::create_directories(dir / "packs");
    std::ofstream(dir / "packs" / "1-1.index") << std::string(100'000, 'x');  // an index whose pack is gone
    RangeCache cache({dir, 200'000});
    const std::vector<std::uint8_t> block(3'000, 7);
    const auto request = [](int i) { return RangeRequest{"http://h/" + std::to_string(i), {{0, 3'000}}, "e"}; };
    for (int i = 0; i < 400; ++i) {
        cache.store(request(i), reply_of({block}));
        if (i % 50 == 49) cache.flush();
    }
    cache.flush();
    EXPECT_LE(folder_bytes(dir), 200'000u);
    EXPECT_TRUE(cache.find(request(399)));
    EXPECT_FALSE(cache.find(request(0)));
    std::size_t packs = 0, indexes = 0;
    for (const auto& e : fs::recursive_directory_iterator(dir)) {
        packs += e.path().extension() == ".pack";
        indexes += e.path().extension() == ".index";
    }
    EXPECT_GT(packs, 1u);
    EXPECT_EQ(packs, indexes) << "an index goes with its pack";
    EXPECT_FALSE(fs::exists(dir / "packs" / "1-1.index")) << "an index without its pack is evicted";
    RangeCache again({dir, 200'000});
    EXPECT_TRUE(again.find(request(399)));
    EXPECT_FALSE(again.find(request(0)));
}

TEST_F(RangeCacheTest, SizeZeroIsOff) {
    RangeCache cache({dir, 0});
    const RangeRequest request{"http://h/a.laz", {{0, 1}}, "e"};
    cache.store(request, reply_of({{1}}));
    EXPECT_FALSE(cache.find(request));
    EXPECT_FALSE(fs::exists(dir));
}

}  // namespace
}  // namespace lidarscout::net
