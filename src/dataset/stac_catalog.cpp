// STAC catalog reading (local or remote, through io::File): a breadth-first walk over the
// documents, each read once, items taken from ItemCollections and Items, links followed from
// Catalogs and Collections (and "next" pages of ItemCollections), all of it bounded.
#include "dataset/stac_catalog.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <deque>
#include <filesystem>
#include <set>
#include <utility>

#include <nlohmann/json.hpp>

#include "core/error.hpp"
#include "dataset/json_file.hpp"
#include "io/file.hpp"
#include "net/origin_policy.hpp"
#include "net/url.hpp"

namespace lidarscout::dataset {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

constexpr int kMaxDepth = 32;  // links followed from the first document

std::string lower_file_name(const std::string& path) {
    const std::string plain = net::is_url(path) ? path.substr(0, path.find_first_of("?#")) : path;
    std::string name = plain.substr(plain.find_last_of('/') + 1);
    std::transform(name.begin(), name.end(), name.begin(), [](unsigned char c) { return std::tolower(c); });
    return name;
}

bool ends_with(const std::string& s, const std::string& end) {
    return s.size() >= end.size() && s.compare(s.size() - end.size(), end.size(), end) == 0;
}

struct Walk {
    const CatalogLimits& limits;
    Catalog out;
    std::set<std::string> seen;                  // documents queued or read
    std::deque<std::pair<std::string, int>> queue;  // documents to read, with their depth
    std::uint64_t bytes = 0;
    bool full = false;  // a limit was reached: nothing more is read

    void error(const std::string& document, const std::string& what) {
        out.errors.push_back(io::display_path(document) + ": " + what);
    }
};

// Whether `s` starts with a URI scheme ("file:", "s3:"; a Windows drive letter is not one).
bool has_scheme(const std::string& s) {
    const auto colon = s.find(':');
    if (colon == std::string::npos || colon < 2 || !std::isalpha(static_cast<unsigned char>(s[0]))) return false;
    return std::all_of(s.begin(), s.begin() + static_cast<std::ptrdiff_t>(colon), [](unsigned char c) {
        return std::isalnum(c) || c == '+' || c == '-' || c == '.';
    });
}

// `href` of `document` as a path or URL: a local document's relative hrefs against its folder (URLs
// and absolute paths as they are); a remote document's against its URL, keeping its origin.
std::optional<std::string> resolve(const std::string& document, const std::string& href, std::string& refusal) {
    if (href.empty()) {
        refusal = "an empty href";
        return std::nullopt;
    }
    const bool other_scheme = !net::is_url(href) && has_scheme(href);
    if (!net::is_url(document)) {
        if (href.rfind("file://", 0) == 0) return href.substr(7);  // a local catalog's file URI
        if (other_scheme) {
            refusal = "\"" + href + "\" is neither a path nor an http(s) URL";
            return std::nullopt;
        }
        if (net::is_url(href) || fs::path(href).is_absolute()) return href;
        return (fs::path(document).parent_path() / href).lexically_normal().string();
    }
    if (other_scheme) {
        refusal = "\"" + href + "\" refused: a remote catalog names http(s) URLs only";
        return std::nullopt;
    }
    std::string url = net::resolve_url(document, href);
    refusal = net::derived_url_refusal(document, url);
    if (!refusal.empty()) {
        refusal = io::display_path(url) + " refused: " + refusal;
        return std::nullopt;
    }
    return url;
}

void follow(const std::string& document, int depth, const std::string& href, Walk& w) {
    std::string refusal;
    const auto target = resolve(document, href, refusal);
    if (!target) return w.error(document, "link not followed: " + refusal);
    if (depth + 1 > kMaxDepth) {
        return w.error(document, "link " + io::display_path(*target) + " not followed: more than " +
                                     std::to_string(kMaxDepth) + " links deep");
    }
    if (w.seen.insert(*target).second) w.queue.emplace_back(*target, depth + 1);
}

// The asset that is the tile: roles holding "data", else the one named "data", else the first.
const json* data_asset(const json& assets) {
    for (const auto& [key, a] : assets.items()) {
        const auto roles = a.find("roles");
        if (a.is_object() && roles != a.end() && roles->is_array() &&
            std::find(roles->begin(), roles->end(), "data") != roles->end()) {
            return &a;
        }
    }
    if (const auto it = assets.find("data"); it != assets.end() && it->is_object()) return &*it;
    for (const auto& a : assets) {
        if (a.is_object()) return &a;
    }
    return nullptr;
}

// The item's pc:count, proj:bbox and CRS; a field of the wrong kind gets a line (the tile is read anyway).
void read_properties(const json& props, const std::string& document, const std::string& name, CatalogItem& item,
                     Walk& w) {
    if (const auto c = props.find("pc:count"); c != props.end() && !c->is_null()) {
        if (c->is_number_unsigned() || (c->is_number_integer() && c->get<std::int64_t>() >= 0)) {
            item.count = c->get<std::uint64_t>();
        } else {
            w.error(document, name + ": pc:count is not a count of points (" + c->dump() + ")");
        }
    }
    if (const auto b = props.find("proj:bbox"); b != props.end() && !b->is_null()) {
        const bool numbers = b->is_array() && (b->size() == 4 || b->size() == 6) &&
                             std::all_of(b->begin(), b->end(), [](const json& v) {
                                 return v.is_number() && std::isfinite(v.get<double>());
                             });
        if (numbers) {
            const std::size_t half = b->size() / 2;
            std::array<double, 6> box{};
            box[2] = box[5] = std::nan("");
            for (std::size_t k = 0; k < half; ++k) box[k] = (*b)[k], box[3 + k] = (*b)[half + k];
            if (box[0] <= box[3] && box[1] <= box[4]) item.bbox = box;
        }
        if (!item.bbox) w.error(document, name + ": proj:bbox is not 4 or 6 numbers, mins before maxes");
    }
    if (const auto e = props.find("proj:epsg"); e != props.end() && e->is_number_integer() && *e > 0) {
        item.crs = "EPSG:" + std::to_string(e->get<std::int64_t>());
    } else if (const auto wkt = props.find("proj:wkt2"); wkt != props.end() && wkt->is_string() &&
                                                         !wkt->get<std::string>().empty()) {
        item.crs = wkt->get<std::string>();
    } else if (const auto pj = props.find("proj:projjson"); pj != props.end() && pj->is_object()) {
        item.crs = pj->dump();
    }
}

void add_item(const json& feature, const std::string& document, std::size_t index, Walk& w) {
    if (w.out.items.size() >= w.limits.max_items) {
        w.full = true;
        return w.error(document, "more than " + std::to_string(w.limits.max_items) + " items: the rest is not read");
    }
    CatalogItem item;
    item.document = io::display_path(document);
    if (!feature.is_object()) return w.error(document, "item #" + std::to_string(index + 1) + " is not a STAC item");
    if (const auto id = feature.find("id"); id != feature.end() && id->is_string()) item.id = *id;
    const std::string name = "item " + (item.id.empty() ? "#" + std::to_string(index + 1) : "'" + item.id + "'");
    if (feature.value("type", json()) != "Feature") return w.error(document, name + " is not a STAC item (a Feature)");
    const auto assets = feature.find("assets");
    const json* asset = assets != feature.end() && assets->is_object() ? data_asset(*assets) : nullptr;
    const auto href = asset ? asset->find("href") : json::const_iterator{};
    if (!asset || href == asset->end() || !href->is_string()) {
        return w.error(document, name + " has no data asset href");
    }
    std::string refusal;
    const auto resolved = resolve(document, href->get<std::string>(), refusal);
    if (!resolved) return w.error(document, name + ": " + refusal);
    item.href = *resolved;
    if (const auto props = feature.find("properties"); props != feature.end() && props->is_object()) {
        read_properties(*props, document, name, item, w);
    }
    w.out.items.push_back(std::move(item));
}

// Follows the links of `doc` whose rel is one of `rels`.
void follow_links(const json& doc, const std::string& document, int depth, std::initializer_list<const char*> rels,
                  Walk& w) {
    const auto links = doc.find("links");
    if (links == doc.end() || !links->is_array()) return;
    for (const auto& link : *links) {
        if (!link.is_object()) continue;
        const std::string rel = link.value("rel", "");
        if (std::none_of(rels.begin(), rels.end(), [&](const char* r) { return rel == r; })) continue;
        const auto href = link.find("href");
        if (href == link.end() || !href->is_string()) {
            w.error(document, "a '" + rel + "' link without an href");
            continue;
        }
        follow(document, depth, *href, w);
    }
}

void read_document(const std::string& document, int depth, Walk& w) {
    json doc;
    try {
        const io::File file = io::File::open(document);
        if (w.bytes + file.size() > w.limits.max_bytes) {
            w.full = true;
            return w.error(document, "the catalog's documents pass " + std::to_string(w.limits.max_bytes >> 20) +
                                         " MiB together: it and the rest are not read");
        }
        w.bytes += file.size();
        doc = read_json_object(file, w.limits.max_document_bytes);
    } catch (const Error& e) {
        w.out.errors.push_back(e.file().empty() ? io::display_path(document) + ": " + e.what() : e.what());
        return;
    }
    ++w.out.documents;
    const std::string type = doc.value("type", json("")).is_string() ? doc.value("type", "") : "";
    if (type == "FeatureCollection") {
        const auto features = doc.find("features");
        if (features == doc.end() || !features->is_array()) {
            return w.error(document, "an ItemCollection without features");
        }
        for (std::size_t i = 0; i < features->size() && !w.full; ++i) add_item((*features)[i], document, i, w);
        follow_links(doc, document, depth, {"next"}, w);  // a STAC API search's further pages
    } else if (type == "Feature") {
        add_item(doc, document, 0, w);
    } else if (type == "Catalog" || type == "Collection") {
        follow_links(doc, document, depth, {"child", "item"}, w);
    } else {
        w.error(document, "not a STAC catalog, collection, item or item collection (its type is '" + type + "')");
    }
}

}  // namespace

bool is_stac_catalog(const std::string& path) {
    const std::string name = lower_file_name(path);
    if (name == "ept.json" || name == "entwine.json") return false;
    return ends_with(name, ".vpc") || ends_with(name, ".json");
}

Catalog read_catalog(const std::string& path, const CatalogLimits& limits) {
    Walk w{limits, {}, {}, {}, 0, false};
    w.seen.insert(path);
    w.queue.emplace_back(path, 0);
    while (!w.queue.empty() && !w.full) {
        if (w.out.documents >= limits.max_documents) {
            w.error(path, "more than " + std::to_string(limits.max_documents) +
                              " catalog documents: the rest is not read");
            break;
        }
        auto [document, depth] = std::move(w.queue.front());
        w.queue.pop_front();
        read_document(document, depth, w);
    }
    return std::move(w.out);
}

std::string item_disagreement(const CatalogItem& item, std::uint64_t count, const std::array<double, 6>& bounds,
                              int epsg) {
    std::vector<std::string> what;
    if (item.count && *item.count != count) {
        what.push_back("pc:count " + std::to_string(*item.count) + ", the header " + std::to_string(count));
    }
    if (item.bbox) {
        const auto& b = *item.bbox;
        const double tolerance = 0.01 * std::max(bounds[3] - bounds[0], bounds[4] - bounds[1]) + 1e-3;
        bool off = false;
        for (int k = 0; k < 6; ++k) {
            if (!std::isnan(b[k]) && std::abs(b[k] - bounds[k]) > tolerance) off = true;
        }
        if (off) what.push_back("proj:bbox differs from the header's bounds by more than 1%");
    }
    if (epsg != 0 && item.crs.rfind("EPSG:", 0) == 0 && item.crs != "EPSG:" + std::to_string(epsg)) {
        what.push_back("proj:epsg " + item.crs.substr(5) + ", the header EPSG:" + std::to_string(epsg));
    }
    std::string out;
    for (const auto& w : what) out += (out.empty() ? "" : "; ") + w;
    return out;
}

}  // namespace lidarscout::dataset
