// EPT metadata and hierarchy reading (local or remote, through io::File): a breadth-first
// walk over the hierarchy files, each read once, with bounded nodes and bytes.
#include "dataset/ept.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <deque>
#include <filesystem>
#include <map>
#include <optional>
#include <set>

#include <nlohmann/json.hpp>

#include "core/error.hpp"
#include "core/json_reader.hpp"
#include "core/text.hpp"
#include "dataset/json_file.hpp"
#include "io/file.hpp"
#include "net/origin_policy.hpp"
#include "net/url.hpp"

namespace lidarscout::dataset {

namespace {

constexpr std::uint64_t kMaxJson = 256u << 20;
constexpr long long kMaxDepth = 64;

using NodeKey = std::array<long long, 4>;  // depth, x, y, z

std::string file_name(const std::string& path) {
    const std::string plain = net::is_url(path) ? path.substr(0, path.find_first_of("?#")) : path;
    return plain.substr(plain.find_last_of('/') + 1);
}

// `relative` (made of node keys, never absolute) next to `path`, in the same folder or URL
// folder; a URL must keep the dataset's origin.
std::string beside(const std::string& path, const std::string& relative) {
    if (!net::is_url(path)) return (std::filesystem::path(path).parent_path() / relative).string();
    std::string url = net::resolve_url(path, relative);
    const std::string refusal = net::derived_url_refusal(path, url);
    if (!refusal.empty()) throw Error(io::display_path(url), std::nullopt, "refused: " + refusal);
    return url;
}

// The numbers of a node key "D-X-Y-Z" (each 0..2^D-1, D at most kMaxDepth), or nothing.
std::optional<NodeKey> parse_key(const std::string& key) {
    NodeKey k{};
    std::size_t at = 0;
    for (std::size_t i = 0; i < k.size(); ++i) {
        const std::size_t end = i + 1 < k.size() ? key.find('-', at) : key.size();
        if (end == std::string::npos || end == at || end - at > 19) return std::nullopt;
        const std::string digits = key.substr(at, end - at);
        if (!std::all_of(digits.begin(), digits.end(), [](unsigned char c) { return std::isdigit(c); })) {
            return std::nullopt;
        }
        k[i] = std::stoll(digits);
        at = end + 1;
    }
    if (k[0] > kMaxDepth) return std::nullopt;
    const long long span = 1ll << k[0];
    if (k[1] >= span || k[2] >= span || k[3] >= span) return std::nullopt;
    return k;
}

nlohmann::json read_json(const io::File& file) { return read_json_object(file, kMaxJson); }

nlohmann::json read_json(const std::string& path) { return read_json(io::File::open(path)); }

// Where the nodes and the hierarchy files of a dataset live, relative to its metadata file.
struct Layout {
    std::string data, hierarchy;  // folders, each ending in '/' ("" for the metadata's own)
};

Layout layout_of(const std::string& metadata_path) {
    if (file_name(metadata_path) == "entwine.json") return {"", "h/"};  // Entwine 1.x
    return {"ept-data/", "ept-hierarchy/"};
}

class HierarchyReader {
public:
    HierarchyReader(const std::string& metadata, const Layout& layout, const EptLimits& limits)
        : metadata_(metadata), layout_(layout), limits_(limits) {}

    // Reads the hierarchy from its root file, each file once.
    void read_all() {
        std::deque<std::string> queue{"0-0-0-0"};
        files_.insert(queue.front());
        while (!queue.empty()) {
            const std::string key = std::move(queue.front());
            queue.pop_front();
            for (auto& next : read_file(key)) {
                if (files_.insert(next).second) queue.push_back(std::move(next));
            }
        }
    }
    // The node paths, ordered by depth then x, y, z.
    std::vector<std::string> tiles() const {
        std::vector<std::string> out;
        for (const auto& [key, name] : nodes_) out.push_back(beside(metadata_, layout_.data + name + ".laz"));
        return out;
    }
    std::uint64_t files_read() const { return files_read_; }

private:
    // Reads the hierarchy file of `key`; returns the keys of the sub-hierarchy files it names.
    std::vector<std::string> read_file(const std::string& key) {
        const auto file = io::File::open(beside(metadata_, layout_.hierarchy + key + ".json"));
        bytes_ += file.size();
        if (bytes_ > limits_.max_hierarchy_bytes) {
            throw Error(file.path(), std::nullopt, "the EPT hierarchy is larger than the limit of " +
                                                       std::to_string(limits_.max_hierarchy_bytes) + " bytes");
        }
        ++files_read_;
        std::vector<std::string> subtrees;
        const auto json = read_json(file);
        for (const auto& item : json.items()) {
            const std::string& node = item.key();
            const auto k = parse_key(node);
            if (!k) {
                throw Error(file.path(), std::nullopt,
                            "hierarchy entry \"" + display_excerpt(node) + "\" is not a node key D-X-Y-Z");
            }
            if (!item.value().is_number_integer()) {
                throw Error(file.path(), std::nullopt, "hierarchy entry " + node + " is not a count");
            }
            if (++entries_ > limits_.max_nodes) {
                throw Error(file.path(), std::nullopt, "the EPT hierarchy has more than the limit of " +
                                                           std::to_string(limits_.max_nodes) + " nodes");
            }
            const auto n = item.value().get<long long>();
            if (n == -1 && node != key) subtrees.push_back(node);
            if (n > 0) nodes_.emplace(*k, node);
        }
        return subtrees;
    }

    const std::string& metadata_;
    const Layout& layout_;
    const EptLimits& limits_;
    std::set<std::string> files_;             // hierarchy files read or queued, by key
    std::map<NodeKey, std::string> nodes_;  // nodes with points
    std::uint64_t bytes_ = 0, entries_ = 0, files_read_ = 0;
};

}  // namespace

bool is_ept_metadata(const std::string& path) {
    const std::string name = file_name(path);
    return name == "ept.json" || name == "entwine.json";
}

EptNodes ept_nodes(const std::string& metadata_path, const EptLimits& limits) {
    EptNodes out;
    try {
        const auto meta = read_json(metadata_path);
        const auto type = json_optional_string(meta, "dataType").value_or("");
        if (type != "laszip") {
            throw Error(io::display_path(metadata_path), std::nullopt,
                        "EPT data type \"" + display_excerpt(type) +
                            "\" is not supported (only laszip nodes are tiles)");
        }
        const Layout layout = layout_of(metadata_path);
        HierarchyReader reader(metadata_path, layout, limits);
        try {
            reader.read_all();
            out.tiles = reader.tiles();
        } catch (const Error&) {
            out.hierarchy_files = reader.files_read();
            throw;
        }
        out.hierarchy_files = reader.files_read();
    } catch (const Error& e) {
        out.errors.push_back(e.file().empty() ? io::display_path(metadata_path) + ": " + e.what() : e.what());
        out.tiles.clear();
    }
    return out;
}

}  // namespace lidarscout::dataset
