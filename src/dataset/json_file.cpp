// Bounded JSON documents from files or URLs.
#include "dataset/json_file.hpp"

#include <algorithm>
#include <deque>
#include <future>
#include <memory>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "net/url.hpp"

namespace lidarscout::dataset {

namespace {

// A remote document read ahead: blocks of kBlock bytes, up to kInFlight of them asked at once, handed on
// in order. Read in the reader's chunks (a megabyte at most), one request at a time, a country's catalog
// (250 MB) over a link of 50 ms would spend 12 s waiting on round trips alone; and a STAC API search's
// page of 1,000 items (1.6 MB: chunks of 64 KB doubling) five round trips where one does.
class ReadAhead {
public:
    static constexpr std::uint64_t kBlock = 8u << 20;
    static constexpr std::size_t kInFlight = 4;

    explicit ReadAhead(const io::File& file) : file_(file) {}

    std::size_t read(std::span<char> out) {
        while (at_ == block_.size()) {
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
            const std::uint64_t offset = next_, size = std::min(kBlock, file_.size() - offset);
            next_ += size;
            ahead_.push_back(std::async(std::launch::async, [this, offset, size] {
                return file_.read_vector(offset, size, "JSON document");  // (a remote block as it came: no copy)
            }));
        }
    }

    const io::File& file_;
    std::uint64_t next_ = 0;
    std::deque<std::future<std::vector<std::uint8_t>>> ahead_;  // (their destructors wait for them)
    std::vector<std::uint8_t> block_;
    std::size_t at_ = 0;
};

}  // namespace

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
