// Bounded JSON documents from files or URLs.
#include "dataset/json_file.hpp"

#include <algorithm>
#include <deque>
#include <future>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "net/url.hpp"

namespace lidarscout::dataset {

namespace {

// A remote document read ahead: blocks of kBlock bytes, up to kInFlight of them asked at once, handed on
// in order. Read in the reader's chunks (a megabyte at most), one request at a time, a country's catalog
// (250 MB) over a link of 50 ms would spend 12 s waiting on round trips alone; and a STAC API search's
// page of 1,000 items (1.6 MB: chunks of 64 KB doubling) five round trips where one does. Eight at once: with
// four, a country's catalog waited on round trips at 50 ms once its blocks' page faults were gone (blocks read
// into the memory of blocks read before): every footprint in 0.97 s against 1.19 (four alternating pairs).
using Block = std::future<std::vector<std::uint8_t>>;
constexpr std::uint64_t kBlock = 8u << 20;
constexpr std::size_t kInFlight = 8;

// Asks for the block at `next` of `file` (it must outlive the block's reading), written into `buffer`'s memory
// where it holds it (io::File::read_vector), and moves `next` past it.
Block ask_block(const io::File& file, std::uint64_t& next, std::vector<std::uint8_t> buffer = {}) {
    const std::uint64_t offset = next, size = std::min(kBlock, file.size() - offset);
    next += size;
    return std::async(std::launch::async, [&file, offset, size, buffer = std::move(buffer)]() mutable {
        return file.read_vector(offset, size, "JSON document", std::move(buffer));  // (a remote block as it came)
    });
}

// Blocks asked for before their reader came (prefetch_json_document): the file they are read from and
// the offset after them.
struct EarlyBlocks {
    std::shared_ptr<const io::File> file;
    std::deque<Block> blocks;
    std::uint64_t next = 0;
};

struct EarlyDocument {
    std::mutex mutex;
    std::string url;
    std::future<EarlyBlocks> blocks;
};

EarlyDocument& early() {
    static EarlyDocument e;
    return e;
}

// The blocks asked for early of `url`, taken (none when none were, or their open failed).
EarlyBlocks take_early(const std::string& url) {
    std::future<EarlyBlocks> blocks;
    {
        std::lock_guard lock(early().mutex);
        if (early().url != url || !early().blocks.valid()) return {};
        blocks = std::move(early().blocks);
        early().url.clear();
    }
    try {
        return blocks.get();
    } catch (const Error&) {  // (the reader's file opened where the early one did not: read as it comes)
        return {};
    }
}

class ReadAhead {
public:
    explicit ReadAhead(const io::File& file) : file_(file) {
        EarlyBlocks e = take_early(file.path());
        if (e.file && e.file->size() == file.size()) {
            early_file_ = std::move(e.file);
            ahead_ = std::move(e.blocks);
            next_ = e.next;
        }
    }

    std::size_t read(std::span<char> out) {
        while (at_ == block_.size()) {
            if (block_.capacity() != 0) spare_.push_back(std::move(block_));  // (its memory for a block to come)
            block_.clear();
            at_ = 0;
            ask();
            if (ahead_.empty()) return 0;
            block_ = ahead_.front().get();  // (a read's Error is thrown here, on the reader's thread)
            ahead_.pop_front();
            at_ = 0;
        }
        const std::size_t n = std::min(out.size(), block_.size() - at_);
        std::copy_n(block_.data() + at_, n, reinterpret_cast<std::uint8_t*>(out.data()));
        at_ += n;
        return n;
    }

private:
    // Asks for the next blocks, up to kInFlight (never past the end: a request to learn nothing is there).
    void ask() {
        while (ahead_.size() < kInFlight && next_ < file_.size()) {
            std::vector<std::uint8_t> buffer;
            if (!spare_.empty()) buffer = std::move(spare_.back()), spare_.pop_back();
            ahead_.push_back(ask_block(file_, next_, std::move(buffer)));
        }
    }

    const io::File& file_;
    std::shared_ptr<const io::File> early_file_;  // what the blocks asked for early read (declared before them)
    std::uint64_t next_ = 0;
    std::deque<Block> ahead_;  // (their destructors wait for them)
    std::vector<std::vector<std::uint8_t>> spare_;  // blocks read, their memory kept for the next (a few)
    std::vector<std::uint8_t> block_;
    std::size_t at_ = 0;
};

}  // namespace

void prefetch_json_document(const std::string& url) {
    if (!net::is_url(url)) return;
    forget_json_prefetch();
    // (the open's one request is the first block's; asked now: the reader's open of `url` waits for it)
    std::future<std::pair<io::File, std::vector<std::uint8_t>>> opening;
    try {
        opening = io::File::open_from_start(url, kBlock);
    } catch (const Error&) {
        return;  // (a URL that cannot be asked for: the reader's own open says why)
    }
    std::lock_guard lock(early().mutex);
    early().url = url;
    early().blocks = std::async(std::launch::async, [opening = std::move(opening)]() mutable {
        EarlyBlocks e;
        auto [file, first] = opening.get();
        e.file = std::make_shared<const io::File>(std::move(file));
        if (!first.empty()) {
            std::promise<std::vector<std::uint8_t>> held;
            e.next = first.size();
            held.set_value(std::move(first));
            e.blocks.push_back(held.get_future());
        }
        while (e.blocks.size() < kInFlight && e.next < e.file->size()) e.blocks.push_back(ask_block(*e.file, e.next));
        return e;
    });
}

void forget_json_prefetch() {
    std::future<EarlyBlocks> dropped;
    {
        std::lock_guard lock(early().mutex);
        dropped = std::move(early().blocks);
        early().url.clear();
    }
    if (dropped.valid()) dropped.wait();  // (its blocks' futures wait for their reads as they go)
}

JsonSource file_json_source(const io::File& file) {
    if (net::is_url(file.path())) {
        return [ahead = std::make_shared<ReadAhead>(file)](std::span<char> out) { return ahead->read(out); };
    }
    return [&file, offset = std::uint64_t{0}](std::span<char> out) mutable -> std::size_t {
        // Never past the end: a remote file would spend a request to learn that nothing is there.
        if (offset >= file.size()) return 0;
        const auto want = static_cast<std::size_t>(std::min<std::uint64_t>(out.size(), file.size() - offset));
        const std::size_t n = file.read_at(offset, {reinterpret_cast<std::uint8_t*>(out.data()), want});
        offset += n;
        return n;
    };
}

nlohmann::json read_json_file(const io::File& file, const JsonLimits& limits, const JsonStreaming* streaming) {
    const std::string name = io::display_path(file.path());
    if (file.size() > limits.max_bytes) {
        throw Error(name, std::nullopt,
                    "JSON file too large (" + std::to_string(file.size()) + " bytes, at most " +
                        std::to_string(limits.max_bytes) + ")");
    }
    return read_json(file_json_source(file), name, limits, streaming);
}

nlohmann::json read_json_object(const io::File& file, const JsonLimits& limits, const JsonStreaming* streaming) {
    auto json = read_json_file(file, limits, streaming);
    if (!json.is_object()) throw Error(io::display_path(file.path()), std::nullopt, "not a JSON object");
    return json;
}

nlohmann::json read_json_object(const io::File& file, std::uint64_t max_bytes) {
    JsonLimits limits;
    limits.max_bytes = max_bytes;
    limits.kept = {max_bytes, max_bytes};
    return read_json_object(file, limits);
}

}  // namespace lidarscout::dataset
