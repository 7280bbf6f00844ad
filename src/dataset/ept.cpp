// EPT metadata and hierarchy reading (local or remote, through io::File).
#include "dataset/ept.hpp"

#include <algorithm>
#include <array>
#include <filesystem>
#include <map>

#include <nlohmann/json.hpp>

#include "core/error.hpp"
#include "io/file.hpp"
#include "net/url.hpp"

namespace lidarscout::dataset {

namespace {

constexpr std::uint64_t kMaxJson = 256u << 20;
constexpr int kMaxHierarchyDepth = 64;

std::string file_name(const std::string& path) {
    const std::string plain = net::is_url(path) ? path.substr(0, path.find_first_of("?#")) : path;
    return plain.substr(plain.find_last_of('/') + 1);
}

// `relative` next to `path` (a sibling in the same folder or URL folder).
std::string beside(const std::string& path, const std::string& relative) {
    if (net::is_url(path)) return net::resolve_url(path, relative);
    return (std::filesystem::path(path).parent_path() / relative).string();
}

nlohmann::json read_json(const std::string& path) {
    const auto file = io::File::open(path);
    if (file.size() > kMaxJson) throw Error(file.path(), std::nullopt, "JSON file too large");
    const auto bytes = file.read_vector(0, static_cast<std::size_t>(file.size()), "JSON document");
    auto json = nlohmann::json::parse(bytes.begin(), bytes.end(), nullptr, false);
    if (json.is_discarded() || !json.is_object()) throw Error(file.path(), std::nullopt, "not a JSON object");
    return json;
}

// Where the nodes and the hierarchy files of a dataset live, relative to its metadata file.
struct Layout {
    std::string data, hierarchy;  // folders, each ending in '/'
};

Layout layout_of(const std::string& metadata_path) {
    if (file_name(metadata_path) == "entwine.json") return {"", "h/"};  // Entwine 1.x
    return {"ept-data/", "ept-hierarchy/"};
}

class HierarchyReader {
public:
    HierarchyReader(const std::string& metadata, const Layout& layout, EptNodes& out)
        : metadata_(metadata), layout_(layout), out_(out) {}

    void read(const std::string& key, int depth) {
        const std::string path = beside(metadata_, layout_.hierarchy + key + ".json");
        if (depth > kMaxHierarchyDepth) throw Error(io::display_path(path), std::nullopt, "EPT hierarchy too deep");
        const auto json = read_json(path);
        for (const auto& item : json.items()) {
            const std::string& node = item.key();
            const auto& count = item.value();
            if (!count.is_number_integer()) {
                throw Error(io::display_path(path), std::nullopt, "hierarchy entry " + node + " is not a count");
            }
            const auto n = count.get<long long>();
            if (n == -1 && node != key) {
                read(node, depth + 1);
            } else if (n > 0) {
                nodes_[node] = beside(metadata_, layout_.data + node + ".laz");
            }
        }
    }
    // The node paths, ordered by depth then x, y, z.
    void finish() {
        std::vector<std::pair<std::array<long long, 4>, std::string>> sorted;
        for (const auto& [key, path] : nodes_) sorted.emplace_back(parse_key(key), path);
        std::sort(sorted.begin(), sorted.end());
        for (auto& [k, path] : sorted) out_.tiles.push_back(std::move(path));
    }

private:
    static std::array<long long, 4> parse_key(const std::string& key) {
        std::array<long long, 4> k{};
        std::size_t at = 0;
        for (auto& v : k) {
            v = std::atoll(key.c_str() + at);
            at = key.find('-', at);
            if (at == std::string::npos) break;
            ++at;
        }
        return k;
    }

    const std::string& metadata_;
    const Layout& layout_;
    EptNodes& out_;
    std::map<std::string, std::string> nodes_;
};

}  // namespace

bool is_ept_metadata(const std::string& path) {
    const std::string name = file_name(path);
    return name == "ept.json" || name == "entwine.json";
}

EptNodes ept_nodes(const std::string& metadata_path) {
    EptNodes out;
    try {
        const auto meta = read_json(metadata_path);
        const auto type = meta.value("dataType", std::string());
        if (type != "laszip") {
            throw Error(io::display_path(metadata_path), std::nullopt,
                        "EPT data type \"" + type + "\" is not supported (only laszip nodes are tiles)");
        }
        const Layout layout = layout_of(metadata_path);
        HierarchyReader reader(metadata_path, layout, out);
        reader.read("0-0-0-0", 0);
        reader.finish();
    } catch (const Error& e) {
        out.errors.push_back(e.file().empty() ? io::display_path(metadata_path) + ": " + e.what() : e.what());
        out.tiles.clear();
    }
    return out;
}

}  // namespace lidarscout::dataset
