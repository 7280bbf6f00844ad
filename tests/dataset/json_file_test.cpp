// dataset/json_file: a remote document read in read-ahead blocks whose memory is used again (the bytes
// the same as the file's, whatever the blocks' order of arrival), and its first blocks asked for early
// (prefetch_json_document): taken by the reader of that URL (no block asked twice), dropped by
// forget_json_prefetch, and a URL that cannot be opened early is no error of the reader's.
#include "dataset/json_file.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "core/error.hpp"
#include "core/json_reader.hpp"
#include "io/file.hpp"
#include "net/http_client.hpp"
#include "nginx_server.hpp"

namespace lidarscout::dataset {
namespace {

namespace fs = std::filesystem;

// A JSON document of `bytes` or a little more: an object holding one array of numbered strings, so that
// every byte's place is checked when it is read back.
std::string numbered_document(std::size_t bytes) {
    std::string text = "{\"lines\": [";
    for (std::size_t i = 0; text.size() < bytes; ++i) {
        text += (i ? ",\"" : "\"") + std::to_string(i) + std::string(90, 'a' + static_cast<char>(i % 26)) + "\"";
    }
    return text + "]}";
}

// What a source gives, in chunks of `chunk` bytes, to its end.
std::string read_all(const JsonSource& source, std::size_t chunk) {
    std::string out, buffer(chunk, '\0');
    while (const std::size_t n = source(std::span(buffer))) out.append(buffer.data(), n);
    return out;
}

fs::path served(const std::string& name, const std::string& text) {
    const fs::path path = test::NginxServer::instance().lists_dir() / name;
    std::ofstream(path, std::ios::binary) << text;
    return path;
}

std::uint64_t requests() { return net::HttpClient::shared().stats().requests; }

// Seven blocks and a short one: the blocks after the fifth are read into the memory of blocks read before.
TEST(JsonFileRemote, ADocumentOfManyBlocksReadsAsTheFileHoldsIt) {
    const std::string text = numbered_document(7 * (8u << 20) + 12345);
    served("many_blocks.json", text);
    const io::File file = io::File::open(test::NginxServer::instance().url("lists/many_blocks.json"));
    EXPECT_EQ(read_all(file_json_source(file), 1 << 20), text);
    EXPECT_EQ(read_all(file_json_source(file), 4093), text);  // (chunks that straddle the blocks' ends)
}

// The blocks asked for early are the reader's: reading the document after prefetch_json_document asks
// for no more than reading another copy of it without (a block asked twice would be one request more).
TEST(JsonFileRemote, BlocksAskedForEarlyAreTakenByTheReader) {
    const std::string text = numbered_document(5 * (8u << 20) + 777);
    served("early_a.json", text);
    served("early_b.json", text);
    const auto& server = test::NginxServer::instance();
    const std::string a = server.url("lists/early_a.json"), b = server.url("lists/early_b.json");
    const io::File file_a = io::File::open(a);
    const io::File file_b = io::File::open(b);  // (both open before counting: their opens are alike)
    std::uint64_t before = requests();
    EXPECT_EQ(read_all(file_json_source(file_a), 1 << 20), text);
    const std::uint64_t plain = requests() - before;
    before = requests();
    prefetch_json_document(b);
    EXPECT_EQ(read_all(file_json_source(file_b), 1 << 20), text);
    EXPECT_EQ(requests() - before, plain) << "the early blocks were asked for again";
    EXPECT_GE(plain, 5u) << "five blocks of 8 MiB asked (the last, short one may lie in the tail the open holds)";
}

// Prefetched before the document is opened, the open is the first block's request: opening and reading it then
// ask for its blocks only (an open of its own had been two requests more: its head, then its tail).
TEST(JsonFileRemote, AnEarlyOpenIsTheFirstBlocksRequest) {
    const std::string text = numbered_document(2 * (8u << 20) + 999);
    served("early_open.json", text);
    const std::string url = test::NginxServer::instance().url("lists/early_open.json");
    const std::uint64_t before = requests();
    prefetch_json_document(url);
    const io::File file = io::File::open(url);
    EXPECT_EQ(read_all(file_json_source(file), 1 << 20), text);
    EXPECT_EQ(requests() - before, 3u) << "three blocks of 8 MiB, the first the open's";
}

// Blocks no reader took are dropped (and their reads waited for); a reader of another URL does not take
// them; an early open that fails says nothing, and the reader's own open names the URL.
TEST(JsonFileRemote, EarlyBlocksOfAnotherUrlOrNoneAreNotTaken) {
    const std::string text = numbered_document(100'000);
    served("early_c.json", text);
    const auto& server = test::NginxServer::instance();
    prefetch_json_document(server.url("lists/early_d_missing.json"));
    const io::File file = io::File::open(server.url("lists/early_c.json"));
    EXPECT_EQ(read_all(file_json_source(file), 4096), text);
    forget_json_prefetch();
    prefetch_json_document(server.url("lists/early_c.json"));
    forget_json_prefetch();
    EXPECT_EQ(read_all(file_json_source(file), 4096), text);
    EXPECT_THROW(io::File::open(server.url("lists/early_d_missing.json")), Error);
    prefetch_json_document("/a/local/path.json");  // (local: nothing asked)
    forget_json_prefetch();
    const std::string bad_port = "http://127.0.0.1:8x/catalog.json";  // (refused before any request)
    EXPECT_NO_THROW(prefetch_json_document(bad_port));
    EXPECT_THROW(io::File::open(bad_port), Error) << "the reader's open says why";
    forget_json_prefetch();
}

}  // namespace
}  // namespace lidarscout::dataset
