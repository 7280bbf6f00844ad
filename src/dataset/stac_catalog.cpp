// STAC catalog reading (local or remote, through io::File): a breadth-first walk over the
// documents, each read once, items taken from ItemCollections and Items, links followed from
// Catalogs and Collections one level deeper, and "next" pages of ItemCollections at the depth of
// their first page, a page loop caught, all of it bounded.
#include "dataset/stac_catalog.hpp"

#include <algorithm>
#include <any>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <deque>
#include <filesystem>
#include <iterator>
#include <set>
#include <string_view>
#include <unordered_map>
#include <utility>

#include <nlohmann/json.hpp>

#include "core/error.hpp"
#include "core/json_reader.hpp"
#include "core/thread_pool.hpp"
#include "core/text.hpp"
#include "dataset/json_file.hpp"
#include "dataset/stac_item_text.hpp"
#include "dataset/tile.hpp"
#include "io/file.hpp"
#include "net/origin_policy.hpp"
#include "net/remote_file.hpp"
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

// `text` from a catalog (an id, an href, a path or URL, a type) as put in a line: cut.
std::string shown(const std::string& text) { return display_excerpt(text); }

// Where an item's lines go: those of items kept (warnings) and of items left out (errors).
struct ItemLineSink {
    std::vector<std::string> warnings, errors;
};

// A document to read: where it lies in the walk. A "next" page is not a link of depth: the pages of
// one search, however many, lie at the depth of its first page.
struct Queued {
    std::string document;
    int depth = 0;
    std::uint64_t page = 0;  // 0 for a document reached by a link of depth; n for the n-th page after one
    std::string first;       // the first page of its search (the document itself when page is 0)
};

// The CRS texts of a catalog's items, each held once however many items name it.
using CrsTexts = std::unordered_map<std::string, SharedText>;

struct Walk {
    const CatalogLimits& limits;
    Catalog out;
    std::set<std::string> seen;   // documents queued or read
    std::deque<Queued> queue;     // documents to read
    std::unordered_map<std::uint64_t, std::uint64_t> pages;  // the items of each page read (a hash): its number
    CrsTexts crs_texts;  // the items' CRS texts, each once
    std::uint64_t bytes = 0;
    bool full = false;  // a limit was reached: nothing more is read
    const SidecarNamed* sidecar_named = nullptr;  // told of the first sidecar link read (then null)

    void error(const std::string& document, const std::string& what) {
        out.errors.push_back(shown(io::display_path(document)) + ": " + what);
    }
    void take_item_lines(ItemLineSink&& lines) {
        out.warnings.insert(out.warnings.end(), lines.warnings.begin(), lines.warnings.end());
        out.errors.insert(out.errors.end(), lines.errors.begin(), lines.errors.end());
    }
};

// What one document's streamed arrays ("features", "links") gave, used once the whole document is
// read and its type known: items (appended to the catalog's as they come) are kept only from an
// ItemCollection read to its end (or to the item limit), links followed only where its type
// follows them.
struct Streamed {
    struct Link {
        std::string rel;    // "" when the link's rel could not be read
        std::string href;   // "" when it has none that can be followed
        std::string error;  // why it cannot be followed ("" when it can)
    };
    std::size_t first_item = 0;  // where its items start in the catalog's
    // Its items as read, in chunks (moved into the catalog's once, when they are kept: a catalog's vector grown
    // an item at a time would leave the pages of each smaller copy behind, as much as the items again).
    std::vector<std::vector<CatalogItem>> items;
    std::size_t item_count = 0;
    ItemLineSink item_lines;     // lines about its items
    std::vector<Link> links;     // the links whose rel is followed somewhere, and broken ones
    std::string overview;        // the href of its kOverviewRel link ("" when none)
};

// Whether `s` starts with a URI scheme ("file:", "s3:"; a Windows drive letter is not one).
bool has_scheme(const std::string& s) {
    const auto colon = s.find(':');
    if (colon == std::string::npos || colon < 2 || !std::isalpha(static_cast<unsigned char>(s[0]))) return false;
    return std::all_of(s.begin(), s.begin() + static_cast<std::ptrdiff_t>(colon), [](unsigned char c) {
        return std::isalnum(c) || c == '+' || c == '-' || c == '.';
    });
}

// The folder of a local document as its relative hrefs are resolved against (normalised, ending in '/', or ""
// for the current folder); nullopt where it cannot be told so.
std::optional<std::string> folder_prefix(const std::string& document) {
    const std::string probe = (fs::path(document).parent_path() / "x").lexically_normal().string();
    if (probe == "x") return "";
    if (probe.size() < 2 || !probe.ends_with("/x")) return std::nullopt;
    return probe.substr(0, probe.size() - 1);
}

// `href` (relative) joined to `folder` (folder_prefix) where it is plain segments (a leading "./" aside; none
// empty, "." or ".."): what lexically_normal makes of them, made without splitting paths; nullopt otherwise.
std::optional<std::string> plain_join(const std::string& folder, std::string_view href) {
    if (href.starts_with("./")) href.remove_prefix(2);
    for (std::size_t at = 0; at <= href.size();) {
        const std::size_t end = std::min(href.find('/', at), href.size());
        const std::string_view segment = href.substr(at, end - at);
        if (segment.empty() || segment == "." || segment == "..") return std::nullopt;
        at = end + 1;
    }
    std::string joined;
    joined.reserve(folder.size() + href.size());
    return joined.append(folder).append(href);
}

// `href` of `document` as a path or URL: a local document's relative hrefs against its folder (URLs
// and absolute paths as they are); a remote document's against its URL, keeping its origin. `folder`, when
// given, is a local document's folder_prefix or a remote one's plain_reference_prefix.
std::optional<std::string> resolve(const std::string& document, const std::string& href, std::string& refusal,
                                   const std::optional<std::string>& folder = std::nullopt) {
    if (href.empty()) {
        refusal = "an empty href";
        return std::nullopt;
    }
    const bool other_scheme = !net::is_url(href) && has_scheme(href);
    if (!net::is_url(document)) {
        if (href.rfind("file://", 0) == 0) return href.substr(7);  // a local catalog's file URI
        if (other_scheme) {
            refusal = "\"" + shown(href) + "\" is neither a path nor an http(s) URL";
            return std::nullopt;
        }
        if (net::is_url(href) || href.front() == '/') return href;
        if (folder) {
            if (auto joined = plain_join(*folder, href)) return joined;
        }
        return (fs::path(document).parent_path() / href).lexically_normal().string();
    }
    if (other_scheme) {
        refusal = "\"" + shown(href) + "\" refused: a remote catalog names http(s) URLs only";
        return std::nullopt;
    }
    if (folder && !net::is_url(href) && href.front() != '/') {  // (plain segments: on the document's origin)
        if (auto joined = plain_join(*folder, href)) return joined;
    }
    std::string url = net::resolve_url(document, href);
    refusal = net::derived_url_refusal(document, url);
    if (!refusal.empty()) {
        refusal = shown(io::display_path(url)) + " refused: " + display_excerpt(refusal, 3 * kExcerptBytes);
        return std::nullopt;
    }
    return url;
}

void follow(const Queued& from, const std::string& href, Walk& w) {
    std::string refusal;
    const auto target = resolve(from.document, href, refusal);
    if (!target) return w.error(from.document, "link not followed: " + refusal);
    if (from.depth + 1 > kMaxDepth) {
        return w.error(from.document, "link " + shown(io::display_path(*target)) + " not followed: more than " +
                                          std::to_string(kMaxDepth) + " links deep");
    }
    if (w.seen.insert(*target).second) w.queue.push_back({*target, from.depth + 1, 0, *target});
}

// "page N of FIRST (PAGE)": a page of a search, for its lines.
std::string page_name(const Queued& page) {
    return "page " + std::to_string(page.page + 1) + " of " + shown(io::display_path(page.first)) +
           (page.page == 0 ? "" : " (" + shown(io::display_path(page.document)) + ")");
}

// Queues the page after `page`; a page read already is a loop: one line, and the pages stop there.
void follow_page(const Queued& page, const std::string& href, Walk& w) {
    std::string refusal;
    const auto target = resolve(page.document, href, refusal);
    if (!target) return w.error(page.document, "next page not followed: " + refusal);
    if (!w.seen.insert(*target).second) {
        return w.error(page.first, page_name(page) + " links to " + shown(io::display_path(*target)) +
                                       " as its next page, read already: a page loop; the pages stop there");
    }
    w.queue.push_back({*target, page.depth, page.page + 1, page.first});
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

// A catalog document: its path or URL, and as shown in lines (made once for all its items).
struct Document {
    Document(const std::string& p, CrsTexts& crs)
        : path(p), shown(lidarscout::dataset::shown(io::display_path(p))),
          folder(net::is_url(p) ? net::plain_reference_prefix(p) : folder_prefix(p)), crs_texts(crs) {}
    const std::string& path;
    SharedText shown;
    std::optional<std::string> folder;  // a local document's folder_prefix, a remote one's plain_reference_prefix
    CrsTexts& crs_texts;

    // `text` as held once for the catalog.
    SharedText crs(std::string&& text) const {
        const auto [at, added] = crs_texts.try_emplace(text);
        if (added) at->second = SharedText(std::move(text));
        return at->second;
    }
};

// What could not be used of one item, each cause with what was done instead, named in one line: the item
// kept, its causes and what was done (a warning); the item left out (no tile), its causes (an error).
struct ItemLines {
    const std::string& document;  // the document as shown
    std::size_t index = 0;         // the item's in it
    const std::string* id = nullptr;  // its id, once read ("" or none: named by its place)
    std::vector<std::pair<std::string, std::string>> causes;  // (cause, what was done instead)

    // "item 'ID' in DOCUMENT", or "item #N in DOCUMENT" for an item without id (made only for a line).
    std::string name() const {
        const std::string what = id && !id->empty() ? "'" + shown(*id) + "'" : "#" + std::to_string(index + 1);
        return "item " + what + " in " + document;
    }
    void add(std::string cause, std::string instead) { causes.emplace_back(std::move(cause), std::move(instead)); }
    std::string kept() const {  // (what was done said once after the causes it follows)
        std::string line = name() + ": ";
        for (std::size_t k = 0; k < causes.size(); ++k) {
            line += (k ? "; " : "") + causes[k].first;
            if (k + 1 == causes.size() || causes[k + 1].second != causes[k].second) line += "; " + causes[k].second;
        }
        return line;
    }
    std::string left_out(const std::string& why) const {
        std::string line = name() + ": ";  // (said as a skipped item: "skipped item 'ID' in DOC: CAUSE")
        const char* separator = "";
        for (const auto& cause : causes) line += separator + cause.first, separator = "; ";
        return why.empty() ? line : line + separator + why;
    }
};

// The header is what a field that could not be used is taken from.
constexpr const char* kHeaderInstead = "the tile's header is read instead";

// Reads a field through a typed accessor; when it throws, its cause is added to `lines` (with
// `instead`, what is done without it) and false returned.
template <typename Read>
bool field(ItemLines& lines, const char* instead, Read&& read) {
    try {
        read();
        return true;
    } catch (const Error& e) {
        lines.add(e.cause(), instead);
        return false;
    }
}

std::optional<std::array<double, 6>> bbox_of(const json& b) {
    if (!b.is_array() || b.size() > 6) return std::nullopt;
    std::array<double, 6> values{};
    for (std::size_t k = 0; k < b.size(); ++k) {
        if (!b[k].is_number() || !std::isfinite(values[k] = b[k].get<double>())) return std::nullopt;
    }
    return proj_bbox(std::span<const double>(values.data(), b.size()));
}

// The item's pc:count, proj:bbox and CRS (its text in `crs`, to be held once: Document::crs); a field of the wrong
// kind is a cause in `lines` (the tile is read anyway).
void read_properties(const json& props, CatalogItem& item, std::string& crs, ItemLines& lines) {
    field(lines, kHeaderInstead, [&] { item.count = json_optional_count(props, "pc:count"); });
    if (const json* b = json_field(props, "proj:bbox")) {
        item.bbox = bbox_of(*b);
        if (!item.bbox) lines.add("proj:bbox is not 4 or 6 numbers, mins before maxes", kHeaderInstead);
    }
    const json* epsg = json_field(props, "proj:epsg");
    const json* wkt = json_field(props, "proj:wkt2");
    const json* projjson = json_field(props, "proj:projjson");
    if (epsg && epsg->is_number_integer() && epsg->get<std::int64_t>() > 0) {
        crs = "EPSG:" + std::to_string(epsg->get<std::int64_t>());
    } else if (wkt && wkt->is_string() && !wkt->get_ref<const std::string&>().empty()) {
        crs = wkt->get<std::string>();
    } else if (projjson && projjson->is_object()) {
        crs = projjson->dump(-1, ' ', false, json::error_handler_t::replace);
    }
}

// Adds the line of an item left out to `sink`: where something is not an item, `return refuse(...)`.
std::nullopt_t refuse(const ItemLines& lines, const std::string& why, ItemLineSink& sink) {
    sink.errors.push_back(lines.left_out(why));
    return std::nullopt;
}

// The item's href resolved into `item`; false when it cannot be (then a line in `sink`).
bool resolve_href(const std::string& href, const Document& document, CatalogItem& item, const ItemLines& lines,
                  ItemLineSink& sink) {
    std::string refusal;
    auto resolved = resolve(document.path, href, refusal, document.folder);
    if (!resolved) return refuse(lines, refusal, sink), false;
    item.href = std::move(*resolved);
    return true;
}

// The item `feature` (the index-th of its document), or nullopt; one line in `sink` when something of it
// could not be used (a warning when it is kept, an error when it is left out). Its CRS's text is left in `crs`
// (Document::crs holds it once). Safe to call from several threads at once.
std::optional<CatalogItem> item_of(const json& feature, const Document& document, std::size_t index,
                                   ItemLineSink& sink, std::string& crs) {
    ItemLines lines{document.shown, index, nullptr, {}};
    if (!feature.is_object()) return refuse(lines, "not a STAC item (an object)", sink);
    CatalogItem item;
    item.document = document.shown;
    field(lines, "the item is named by its place", [&] { item.id = json_optional_string(feature, "id").value_or(""); });
    lines.id = &item.id;
    std::optional<std::string> type;
    if (!field(lines, "", [&] { type = json_optional_string(feature, "type"); })) return refuse(lines, "", sink);
    if (type != "Feature") return refuse(lines, "not a STAC item (its type is not \"Feature\")", sink);
    const json* assets = nullptr;
    if (!field(lines, "", [&] { assets = json_optional_object(feature, "assets"); })) return refuse(lines, "", sink);
    const json* asset = assets ? data_asset(*assets) : nullptr;
    std::optional<std::string> href;
    if (asset && !field(lines, "", [&] { href = json_optional_string(*asset, "href"); })) {
        return refuse(lines, "", sink);
    }
    if (!href) return refuse(lines, "no data asset with an href (the tile's path or URL)", sink);
    if (!resolve_href(*href, document, item, lines, sink)) return std::nullopt;
    const json* props = nullptr;
    field(lines, kHeaderInstead, [&] { props = json_optional_object(feature, "properties"); });
    if (props) read_properties(*props, item, crs, lines);
    if (!lines.causes.empty()) sink.warnings.push_back(lines.kept());
    return item;
}

// An item as the thread that parsed it made it (JsonStreaming::prepare): the item (nullopt when left out), its
// CRS's text, its lines. Kept in order on the reading thread (take_element).
struct PreparedItem {
    std::optional<CatalogItem> item;
    std::string crs;
    ItemLineSink lines;
};

PreparedItem prepared_item(const json& feature, const Document& document, std::size_t index) {
    PreparedItem p;
    p.item = item_of(feature, document, index, p.lines, p.crs);
    return p;
}

// What item_of makes of an item of the plain shape (dataset/stac_item_text.hpp), from its fields.
PreparedItem prepared_item(PlainItem&& plain, const Document& document, std::size_t index) {
    PreparedItem p;
    CatalogItem item;
    item.document = document.shown;
    item.id = std::move(plain.id);
    const ItemLines lines{document.shown, index, &item.id, {}};
    if (!resolve_href(plain.href, document, item, lines, p.lines)) return p;
    item.count = plain.count;
    item.bbox = plain.bbox;
    p.crs = std::move(plain.crs);
    p.item = std::move(item);
    return p;
}

// The prepared item kept: its CRS held once, its lines added to `sink`.
std::optional<CatalogItem> kept_item(PreparedItem&& p, const Document& document, ItemLineSink& sink) {
    if (p.item && !p.crs.empty()) p.item->crs = document.crs(std::move(p.crs));
    for (auto& line : p.lines.warnings) sink.warnings.push_back(std::move(line));
    for (auto& line : p.lines.errors) sink.errors.push_back(std::move(line));
    return std::move(p.item);
}

bool followed_somewhere(const std::string& rel) { return rel == "next" || rel == "child" || rel == "item"; }

void take_link(const json& link, std::size_t index, Streamed& s) {
    if (!link.is_object()) return;
    std::optional<std::string> rel, href;
    try {
        rel = json_optional_string(link, "rel");
    } catch (const Error& e) {
        return s.links.push_back({"", "", "link #" + std::to_string(index + 1) + ": " + e.cause()});
    }
    if (rel == kOverviewRel) {
        const json* href = json_field(link, "href");
        if (href && href->is_string()) s.overview = href->get<std::string>();
        return;
    }
    if (!rel || !followed_somewhere(*rel)) return;
    try {
        href = json_optional_string(link, "href");
    } catch (const Error&) {
    }
    if (!href) return s.links.push_back({*rel, "", "a '" + *rel + "' link without an href"});
    s.links.push_back({*rel, std::move(*href), ""});
}

// Whether the catalog holds its limit of items already, with `read` items of the document being read (not yet
// kept): then nothing more is read, and a line says so.
bool at_item_limit(const std::string& document, std::size_t read, Walk& w) {
    if (w.out.items.size() + read < w.limits.max_items) return false;
    w.full = true;
    w.error(document, "more than " + std::to_string(w.limits.max_items) + " items: the rest is not read");
    return true;
}

// What a thread that parsed an element of the document's "features" or "links" makes of it: a PreparedItem of a
// feature, the link itself.
std::any prepare_element(const std::string& key, std::size_t index, json&& element, const Document& document) {
    if (key == "links") return std::move(element);
    return prepared_item(element, document, index);
}

// Takes one element of the document's "features" or "links", as prepare_element made it; false when the item
// limit is reached.
bool take_element(const std::string& key, std::size_t index, std::any&& element, const Document& document,
                  Streamed& s, Walk& w) {
    if (key == "links") {
        take_link(std::any_cast<const json&>(element), index, s);
        if (w.sidecar_named && !s.overview.empty()) {
            std::string refusal;  // (one that cannot be resolved is a line once the document is read: take_overview)
            if (const auto sidecar = resolve(document.path, s.overview, refusal)) (*w.sidecar_named)(*sidecar);
            w.sidecar_named = nullptr;
        }
        return true;
    }
    if (at_item_limit(document.path, s.item_count, w)) return false;
    if (auto item = kept_item(std::any_cast<PreparedItem&&>(std::move(element)), document, s.item_lines)) {
        constexpr std::size_t kChunk = 4096;
        if (s.items.empty() || s.items.back().size() == kChunk) {
            s.items.emplace_back();
            if (s.items.size() > 1) s.items.back().reserve(kChunk);  // (the first grows as it fills)
        }
        s.items.back().push_back(std::move(*item));
        ++s.item_count;
    }
    return true;
}

// Moves the items `s` read into the catalog's (the vector grown to hold them at once), chunk by chunk.
void keep_items(Streamed& s, Walk& w) {
    auto& items = w.out.items;
    if (items.capacity() < items.size() + s.item_count) {
        items.reserve(std::max(items.size() + s.item_count, items.empty() ? 0 : 2 * items.capacity()));
    }
    for (auto& chunk : s.items) {
        std::move(chunk.begin(), chunk.end(), std::back_inserter(items));
        std::vector<CatalogItem>().swap(chunk);
    }
    s.items.clear();
    s.item_count = 0;
}

// Follows the links whose rel is one of `rels` (a line for each broken link that could be one): "next"
// as the page after `q`, the others one link deeper.
void follow_links(const Streamed& s, const Queued& q, std::initializer_list<const char*> rels, Walk& w) {
    for (const auto& link : s.links) {
        const bool wanted = std::any_of(rels.begin(), rels.end(), [&](const char* r) { return link.rel == r; });
        if (!link.rel.empty() && !wanted) continue;
        if (!link.error.empty()) {
            w.error(q.document, link.error);
        } else if (!w.full) {
            link.rel == "next" ? follow_page(q, link.href, w) : follow(q, link.href, w);
        }
    }
}

// A hash of the items `q` gave (from `first`), to tell a page that repeats another whatever its URL.
std::uint64_t items_hash(const Walk& w, std::size_t first) {
    std::uint64_t h = 1469598103934665603ull;
    for (std::size_t i = first; i < w.out.items.size(); ++i) {
        h = (h ^ std::hash<std::string_view>{}(w.out.items[i].href)) * 1099511628211ull;
    }
    return h;
}

// Whether the page `q` (its items from `first`) repeats the items of a page read before: then they are
// dropped, one line says so and its pages stop there.
bool repeats_a_page(const Queued& q, std::size_t first, Walk& w) {
    if (w.out.items.size() == first) return false;
    const auto [at, added] = w.pages.emplace(items_hash(w, first), q.page);
    if (added || q.page == 0) return false;
    w.out.items.resize(first);
    w.error(q.first, page_name(q) + " repeats the items of page " + std::to_string(at->second + 1) +
                         ": a page loop; the pages stop there");
    return true;
}

// What an item holds that the catalog does not use, wherever it lies (read past, not kept even for a while).
const std::vector<std::string> kUnusedKeys{"geometry",     "bbox",         "stac_extensions",
                                           "pc:schemas",   "proj:geometry", "stac_version",
                                           "datetime",     "pc:type",      "pc:encoding"};

// The document's JSON, its "features" and "links" streamed into `s`; nullopt when it could not be read.
std::optional<json> read_streamed(const std::string& document, Streamed& s, Walk& w) {
    JsonLimits limits;
    limits.max_bytes = w.limits.max_document_bytes;
    limits.kept = limits.element = {200'000, 32u << 20};
    // (what an item holds that the catalog does not use is read past, not kept even for a while)
    JsonValueDropper unused;
    const Document named(document, w.crs_texts);
    JsonStreaming streaming{{"features", "links"}, {}, kUnusedKeys, &unused};
    streaming.threads = ThreadPool::shared_size();  // (a country's 250 MB: every core parses items)
    streaming.prepare = [&](const std::string& key, std::size_t i, json&& element) {
        return prepare_element(key, i, std::move(element), named);
    };
    streaming.prepare_text = [&](const std::string& key, std::size_t i, std::string_view text) -> std::any {
        if (key != "features") return {};
        auto plain = read_plain_item(text, kUnusedKeys);
        if (!plain) return {};
        return prepared_item(std::move(*plain), named, i);
    };
    streaming.prepared = [&](const std::string& key, std::size_t i, std::any&& element) {
        return take_element(key, i, std::move(element), named, s, w);
    };
    try {
        const io::File file = io::File::open(document);
        if (w.bytes + file.size() > w.limits.max_bytes) {
            w.full = true;
            w.error(document, "the catalog's documents pass " + std::to_string(w.limits.max_bytes >> 20) +
                                  " MiB together: it and the rest are not read");
            return std::nullopt;
        }
        w.bytes += file.size();
        return read_json_object(file, limits, &streaming);
    } catch (const Error& e) {
        w.out.errors.push_back(e.file().empty() ? shown(io::display_path(document)) + ": " + e.what() : e.what());
        return std::nullopt;
    }
}

// The sidecar the first ItemCollection names, resolved as an item's href (one that cannot be is a line).
void take_overview(const Streamed& s, const std::string& document, Walk& w) {
    if (s.overview.empty() || !w.out.overview.empty()) return;
    std::string refusal;
    if (auto target = resolve(document, s.overview, refusal)) return void(w.out.overview = std::move(*target));
    w.out.warnings.push_back(shown(io::display_path(document)) + ": overview sidecar not used: " + refusal);
}

void read_document(const Queued& q, Walk& w) {
    const std::string& document = q.document;
    Streamed s{w.out.items.size(), {}, 0, {}, {}, {}};
    const bool was_full = w.full;
    const auto doc = read_streamed(document, s, w);
    std::optional<std::string> type;
    std::string type_error;
    try {
        if (doc) type = json_optional_string(*doc, "type");
    } catch (const Error& e) {
        type_error = e.cause();
    }
    // Its items are kept from an ItemCollection read whole (or to the item limit, which may leave a
    // "type" written after them unread).
    const bool collection =
        doc && type_error.empty() && (type == "FeatureCollection" || (!type && w.full && !was_full));
    const json* features = collection ? json_field(*doc, "features") : nullptr;
    if (features && features->is_array()) keep_items(s, w);
    if (!doc) return;
    ++w.out.documents;
    if (!type_error.empty()) {
        w.error(document, "not a STAC catalog: " + type_error);
    } else if (collection) {
        if (!features || !features->is_array()) return w.error(document, "an ItemCollection without features");
        if (repeats_a_page(q, s.first_item, w)) return;
        w.take_item_lines(std::move(s.item_lines));
        take_overview(s, document, w);
        follow_links(s, q, {"next"}, w);  // a STAC API search's further pages
    } else if (type == "Feature") {
        if (at_item_limit(document, 0, w)) return;
        ItemLineSink lines;
        const Document named(document, w.crs_texts);
        if (auto item = kept_item(prepared_item(*doc, named, 0), named, lines)) w.out.items.push_back(std::move(*item));
        w.take_item_lines(std::move(lines));
    } else if (type == "Catalog" || type == "Collection") {
        follow_links(s, q, {"child", "item"}, w);
    } else {
        w.error(document, "not a STAC catalog, collection, item or item collection (its type is '" +
                              shown(type.value_or("")) + "')");
    }
}

}  // namespace

bool is_stac_catalog(const std::string& path) {
    const std::string name = lower_file_name(path);
    if (name == "ept.json" || name == "entwine.json") return false;
    return ends_with(name, ".vpc") || ends_with(name, ".json");
}

namespace {

// What a Content-Type says of the content (parameters and case aside); nullopt when it does not tell.
std::optional<ContentKind> kind_of_type(const std::string& content_type) {
    std::string type = content_type.substr(0, content_type.find(';'));
    std::transform(type.begin(), type.end(), type.begin(), [](unsigned char c) { return std::tolower(c); });
    type.erase(0, type.find_first_not_of(" \t"));
    type.erase(type.find_last_not_of(" \t") + 1);
    if (type == "application/json" || (type.rfind("application/", 0) == 0 && ends_with(type, "+json"))) {
        return ContentKind::catalog;
    }
    if (type == "application/vnd.laszip" || type == "application/vnd.las") return ContentKind::tile;
    return std::nullopt;
}

}  // namespace

ContentKind content_kind(const std::string& path) {
    char head[256];
    std::size_t n = 0;
    try {
        const io::File file = io::File::open(path);
        if (file.remote()) {
            if (const auto kind = kind_of_type(file.remote()->content_type())) return *kind;
        }
        const auto want = static_cast<std::size_t>(std::min<std::uint64_t>(sizeof head, file.size()));
        n = file.read_at(0, std::span(reinterpret_cast<std::uint8_t*>(head), want));
    } catch (const Error&) {
        return ContentKind::other;
    }
    std::string_view text(head, n);
    if (text.starts_with("LASF")) return ContentKind::tile;
    if (text.starts_with("\xEF\xBB\xBF")) text.remove_prefix(3);
    const auto first = text.find_first_not_of(" \t\r\n");
    return first != std::string_view::npos && text[first] == '{' ? ContentKind::catalog : ContentKind::other;
}

bool holds_json_object(const std::string& path) { return content_kind(path) == ContentKind::catalog; }

Catalog read_catalog(const std::string& path, const CatalogLimits& limits, const CatalogItemsRead& items_read,
                     const SidecarNamed& sidecar_named) {
    Walk w{limits, {}, {}, {}, {}, {}, 0, false, sidecar_named ? &sidecar_named : nullptr};
    w.seen.insert(path);
    w.queue.push_back({path, 0, 0, path});
    while (!w.queue.empty() && !w.full) {
        if (w.out.documents >= limits.max_documents) {
            w.error(path, "more than " + std::to_string(limits.max_documents) +
                              " catalog documents: the rest is not read");
            break;
        }
        const Queued q = std::move(w.queue.front());
        w.queue.pop_front();
        const std::size_t before = w.out.items.size();
        read_document(q, w);
        if (items_read && w.out.items.size() > before) items_read(w.out, before, !w.queue.empty() && !w.full);
    }
    return std::move(w.out);
}

std::string item_name(const CatalogItem& item) {
    const std::string what = item.id.empty() ? shown(io::display_path(item.href)) : "'" + shown(item.id) + "'";
    return "item " + what + " in " + item.document.str();
}

namespace {

std::string box_text(const std::array<double, 6>& b) {
    char text[160];
    std::snprintf(text, sizeof text, "x %.2f .. %.2f, y %.2f .. %.2f", b[0], b[3], b[1], b[4]);
    return text;
}

}  // namespace

std::string item_disagreement(const CatalogItem& item, const Tile& tile) {
    const auto& h = tile.header;
    const std::uint64_t count = h.point_count;
    const std::array<double, 6> bounds = {h.min[0], h.min[1], h.min[2], h.max[0], h.max[1], h.max[2]};
    const int epsg = tile.crs().epsg.value_or(0);
    std::vector<std::string> what;
    if (item.count && *item.count != count) {
        what.push_back("pc:count: catalog " + std::to_string(*item.count) + ", header " + std::to_string(count));
    }
    if (item.bbox) {
        const auto& b = *item.bbox;
        const double tolerance = 0.01 * std::max(bounds[3] - bounds[0], bounds[4] - bounds[1]) + 1e-3;
        bool off = false;
        for (int k = 0; k < 6; ++k) {
            if (!std::isnan(b[k]) && std::abs(b[k] - bounds[k]) > tolerance) off = true;
        }
        if (off) {
            what.push_back("proj:bbox: catalog " + box_text(b) + ", header " + box_text(bounds) +
                           " (more than 1% apart)");
        }
    }
    const std::string& crs = item.crs;
    if (epsg != 0 && crs.rfind("EPSG:", 0) == 0 && crs != "EPSG:" + std::to_string(epsg)) {
        what.push_back("proj:epsg: catalog " + crs.substr(5) + ", header " + std::to_string(epsg));
    }
    if (what.empty()) return {};
    std::string line = item_name(item) + " disagrees with the header of its tile";
    if (!item.id.empty()) line += " " + shown(io::display_path(item.href));
    for (std::size_t k = 0; k < what.size(); ++k) line += (k ? "; " : ": ") + what[k];
    return line + (what.size() == 1 ? "; the header's value is used" : "; the header's values are used");
}

}  // namespace lidarscout::dataset
