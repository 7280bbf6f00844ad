// Recursive search for .las/.laz files, tile lists (local or remote), URLs and s3 prefixes.
#include "dataset/file_search.hpp"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <optional>
#include <system_error>

#include "core/error.hpp"
#include "core/thread_pool.hpp"
#include "dataset/ept.hpp"
#include "dataset/json_file.hpp"
#include "dataset/s3_prefix.hpp"
#include "dataset/overview_sidecar.hpp"
#include "dataset/source_identity.hpp"
#include "dataset/stac_catalog.hpp"
#include "dataset/virtual_replica.hpp"
#include "io/file.hpp"
#include "net/origin_policy.hpp"
#include "net/s3_request.hpp"
#include "net/url.hpp"

namespace lidarscout::dataset {

namespace fs = std::filesystem;

namespace {
constexpr std::size_t kMaxTileList = 64u << 20;  // a list of a million URLs
}  // namespace

bool has_point_cloud_extension(const std::string& path) {
    // (a URL's query and fragment are not part of its file name)
    const std::string name = net::is_url(path) ? path.substr(0, path.find_first_of("?#")) : path;
    std::string ext = fs::path(name).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
    return ext == ".las" || ext == ".laz";
}

namespace {

void search_folder(const fs::path& dir, FoundFiles& out) {
    std::vector<std::string> found;
    std::error_code ec;
    fs::recursive_directory_iterator it(dir, fs::directory_options::skip_permission_denied, ec), end;
    for (; !ec && it != end; it.increment(ec)) {
        std::error_code fec;
        if (it->is_regular_file(fec) && has_point_cloud_extension(it->path().string())) {
            found.push_back(it->path().string());
        }
    }
    if (ec) out.errors.push_back({dir.string(), dir.string() + ": cannot list folder: " + ec.message()});
    if (!ec && found.empty()) {
        out.errors.push_back(
            {dir.string(), dir.string() + ": no .las or .laz file in this folder (searched recursively)"});
    }
    std::sort(found.begin(), found.end());
    out.files.insert(out.files.end(), found.begin(), found.end());
}

std::string trim(const std::string& s) {
    const auto first = s.find_first_not_of(" \t\r\n");
    if (first == std::string::npos) return {};
    return s.substr(first, s.find_last_not_of(" \t\r\n") - first + 1);
}

// The first `n` bytes of a file or URL (fewer when it is shorter).
std::string read_head(const io::File& file, std::size_t n) {
    std::string head(static_cast<std::size_t>(std::min<std::uint64_t>(n, file.size())), '\0');
    head.resize(file.read_at(0, std::span(reinterpret_cast<std::uint8_t*>(head.data()), head.size())));
    return head;
}

// A tile list's entry as a path or URL: URLs as they are, relative entries against the list's
// URL or folder. A remote list's entries keep its origin (net/origin_policy.hpp); nothing
// when refused (the reason in `out.errors`).
std::optional<std::string> resolve_entry(const std::string& list, const std::string& entry, FoundFiles& out) {
    if (!net::is_url(list)) {
        if (net::is_url(entry) || fs::path(entry).is_absolute()) return entry;
        return (fs::path(list).parent_path() / entry).string();
    }
    std::string url = net::resolve_url(list, entry);
    const std::string refusal = net::derived_url_refusal(list, url);
    if (refusal.empty()) return url;
    out.errors.push_back({io::display_path(url), io::display_path(url) + ": refused (an entry of the tile list " +
                                                     io::display_path(list) + "): " + refusal});
    return std::nullopt;
}

// The entries of a tile list (a file or a URL), resolved (entries refused by the origin policy are
// reported in `out`); nullopt when the list cannot be read (reported too).
std::optional<std::vector<std::string>> read_tile_list(const std::string& list, FoundFiles& out) {
    std::string text;
    try {
        text = read_head(io::File::open(list), kMaxTileList + 1);
    } catch (const Error& e) {
        out.errors.push_back({io::display_path(list), std::string(e.what()) + " (tile list)"});
        return std::nullopt;
    }
    if (text.size() > kMaxTileList) {
        out.errors.push_back({io::display_path(list), io::display_path(list) + ": tile list larger than " +
                                        std::to_string(kMaxTileList >> 20) + " MiB"});
        return std::nullopt;
    }
    std::vector<std::string> entries;
    std::size_t start = 0;
    while (start < text.size()) {
        auto end = text.find('\n', start);
        if (end == std::string::npos) end = text.size();
        const std::string line = trim(text.substr(start, end - start));
        start = end + 1;
        if (line.empty() || line[0] == '#') continue;
        if (auto entry = resolve_entry(list, line, out)) entries.push_back(std::move(*entry));
    }
    return entries;
}

void expand(const std::string& p, bool allow_lists, FoundFiles& out, const SourcesArriving* arriving = nullptr);

// A tile list's entries, expanded. When none of them names anything (a CSV of points, a text file
// given by mistake), the list gets one line saying so instead of a line per entry.
void expand_list(const std::string& list, FoundFiles& out) {
    const std::size_t errors_before = out.errors.size();
    const auto read = read_tile_list(list, out);
    if (!read) return;  // unreadable: already said
    const std::vector<std::string>& entries = *read;
    const bool refused = out.errors.size() > errors_before;
    const bool nothing = !entries.empty() && std::none_of(entries.begin(), entries.end(), [](const std::string& e) {
        std::error_code ec;
        return net::is_url(e) || fs::exists(e, ec);
    });
    if (nothing) {
        out.errors.push_back({io::display_path(list), io::display_path(list) +
                                                          ": not a LAS/LAZ file nor a tile list (none of its " +
                                                          std::to_string(entries.size()) +
                                                          " lines names a file, folder or URL)"});
        return;
    }
    if (entries.empty() && !refused) {
        out.errors.push_back({io::display_path(list), io::display_path(list) + ": tile list without entries"});
    }
    FoundFiles found;
    for (const auto& entry : entries) expand(entry, false, found);
    out.files.insert(out.files.end(), found.files.begin(), found.files.end());
    for (auto& e : found.errors) out.errors.push_back({e.path, io::display_path(list) + ": " + e.error});
    out.warnings.append(found.warnings);
}

void expand_catalog(const std::string& path, FoundFiles& out, const SourcesArriving* arriving);

// A URL: a LAS/LAZ file, or (when lists are allowed) a STAC catalog or a tile as its Content-Type or content
// says (content_kind), else a tile list; folders cannot be listed.
void expand_url(const std::string& url, bool allow_lists, FoundFiles& out, const SourcesArriving* arriving) {
    if (!allow_lists || has_point_cloud_extension(url)) return out.files.push_back(url);
    switch (content_kind(url)) {
        case ContentKind::catalog: return expand_catalog(url, out, arriving);
        case ContentKind::tile: return out.files.push_back(url);
        case ContentKind::other: return expand_list(url, out);
    }
}

// An EPT dataset's metadata file: its LAZ nodes are the tiles.
void expand_ept(const std::string& metadata, FoundFiles& out) {
    auto nodes = ept_nodes(metadata);
    out.files.insert(out.files.end(), nodes.tiles.begin(), nodes.tiles.end());
    for (auto& e : nodes.errors) out.errors.push_back({io::display_path(metadata), std::move(e)});
}

// The items of a catalog's document just read (from `first`), as tiles to `arriving`; none for its last document
// (what find_tile_sources returns holds them: a country's catalog in one document is not copied item by item).
void announce_items(const Catalog& so_far, std::size_t first, bool more, const SourcesArriving& arriving) {
    if (!more) return arriving({}, false);
    const auto overview = so_far.overview.empty() ? nullptr : std::make_shared<const std::string>(so_far.overview);
    std::vector<TileSource> sources;
    sources.reserve(so_far.items.size() - first);
    for (std::size_t i = first; i < so_far.items.size(); ++i) {
        auto item = std::make_shared<CatalogItem>(so_far.items[i]);
        item->overview = overview;
        sources.push_back({item->href, std::nullopt, {}, std::move(item)});
    }
    arriving(sources, more);
}

// A STAC catalog or virtual point cloud: its items' data assets are the tiles (told to `arriving`, when
// given, a document at a time).
void expand_catalog(const std::string& path, FoundFiles& out, const SourcesArriving* arriving) {
    CatalogItemsRead items_read;
    if (arriving && *arriving) {
        items_read = [arriving](const Catalog& so_far, std::size_t first, bool more) {
            announce_items(so_far, first, more, *arriving);
        };
    }
    struct DecodeOnLeaving {  // (a read that throws leaves no prefetch waiting)
        ~DecodeOnLeaving() {
            decode_overview_prefetch();
            forget_json_prefetch();  // (blocks of another document asked for early: not read on)
        }
    } decode_on_leaving;
    Catalog catalog = read_catalog(path, {}, items_read, prefetch_overview_sidecar);
    decode_overview_prefetch();  // (its items read: the sidecar's decoding has the cores)
    for (auto& e : catalog.errors) out.errors.push_back({io::display_path(path), std::move(e)});
    for (auto& w : catalog.warnings) {
        out.warnings.add({DiagnosticLevel::warning, io::display_path(path), std::nullopt, std::move(w)});
    }
    if (catalog.items.empty() && catalog.errors.empty()) {
        out.errors.push_back({io::display_path(path), io::display_path(path) + ": a STAC catalog without items"});
    }
    const auto overview = catalog.overview.empty() ? nullptr : std::make_shared<const std::string>(catalog.overview);
    // Each item its file and its shared copy, by index in blocks on the shared pool (a country's 152,100, one
    // after the other, had taken 40 ms before its footprints showed).
    const std::size_t n = catalog.items.size(), files = out.files.size(), items = out.items.size();
    out.files.resize(files + n);
    out.items.resize(items + n);
    ThreadPool::shared().for_each_block(n, 2048, [&](std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i) {
            CatalogItem& item = catalog.items[i];
            item.overview = overview;
            out.files[files + i] = item.href;
            out.items[items + i] = {files + i, std::make_shared<const CatalogItem>(std::move(item))};
        }
    });
}

// An s3 prefix: its LAS/LAZ objects.
void expand_s3_prefix(const std::string& prefix, FoundFiles& out) {
    try {
        const auto tiles = s3_prefix_tiles(prefix);
        out.files.insert(out.files.end(), tiles.begin(), tiles.end());
    } catch (const Error& e) {
        out.errors.push_back({prefix, e.what()});
    }
}

// An s3 URL without a trailing slash that names no object: opened as the prefix URL + "/" when objects
// lie under it (s3://bucket/folder whose keys start with folder/), as a local folder opens without its
// trailing slash, with a note saying so; else the open's error is its line. False when it names an
// object. Costs one ListObjectsV2 request of one key, and only after the open failed.
bool expand_missing_object(const std::string& url, FoundFiles& out) {
    try {
        io::File::open(url);
        return false;
    } catch (const Error& e) {
        if (!s3_prefix_has_objects(url + "/")) return out.errors.push_back({io::display_path(url), e.what()}), true;
    }
    const std::string shown = io::display_path(url);
    out.warnings.add({DiagnosticLevel::note, shown, std::nullopt,
                      shown + " is not an object: opened as the prefix " + shown + "/ (the objects under it)"});
    expand_s3_prefix(url + "/", out);
    return true;
}

void expand(const std::string& p, bool allow_lists, FoundFiles& out, const SourcesArriving* arriving) {
    if (const std::string problem = net::url_problem(p); !problem.empty()) {
        return out.errors.push_back({io::display_path(p), io::display_path(p) + ": " + problem});
    }
    if (is_s3_prefix(p)) return expand_s3_prefix(p, out);
    if (net::is_s3_url(p) && !has_point_cloud_extension(p) && expand_missing_object(p, out)) return;
    if (is_ept_metadata(p)) return expand_ept(p, out);
    if (allow_lists && is_stac_catalog(p)) return expand_catalog(p, out, arriving);
    if (net::is_url(p)) return expand_url(p, allow_lists, out, arriving);
    std::error_code ec;
    auto st = fs::status(p, ec);
    if (ec || !fs::exists(st)) {
        out.errors.push_back({p, p + ": no such file or folder"});
    } else if (fs::is_directory(st)) {
        search_folder(p, out);
    } else if (allow_lists && is_tile_list(p)) {
        holds_json_object(p) ? expand_catalog(p, out, arriving) : expand_list(p, out);  // (a catalog by its content)
    } else {
        out.files.push_back(p);
    }
}

}  // namespace

bool is_tile_list(const std::string& path) {
    if (has_point_cloud_extension(path)) return false;
    std::string head;
    try {
        head = read_head(io::File::open(path), 4096);
    } catch (const Error&) {
        return false;  // unreadable: kept as a file, whose reading reports the cause
    }
    if (head.rfind("LASF", 0) == 0) return false;
    return head.find('\0') == std::string::npos;  // text, not a binary file of another kind
}

FoundFiles find_point_cloud_files(const std::vector<std::string>& paths) {
    FoundFiles out;
    for (const auto& p : paths) expand(p, true, out);
    return out;
}

namespace {

// A folder that holds a virtual replica's manifest is that replica (its own folder has no tiles).
std::string replica_or_path(const std::string& p) {
    std::error_code ec;
    if (net::is_url(p) || !fs::is_directory(p, ec)) return p;
    const std::string manifest = (fs::path(p) / kReplicaManifestName).string();
    return fs::is_regular_file(manifest, ec) && is_virtual_replica(manifest) ? manifest : p;
}

}  // namespace

FoundSources find_tile_sources(const std::vector<std::string>& given, const SourcesArriving& arriving) {
    FoundSources out;
    for (const auto& g : given) {
        const std::string p = replica_or_path(g);
        if (!is_virtual_replica(p)) {
            FoundFiles found;
            expand(p, true, found, &arriving);
            out.sources.reserve(out.sources.size() + found.files.size());
            auto item = found.items.begin();
            for (std::size_t i = 0; i < found.files.size(); ++i) {
                const bool named = item != found.items.end() && item->first == i;
                auto what = named ? std::move(item->second) : nullptr;
                out.sources.push_back({std::move(found.files[i]), std::nullopt, {}, std::move(what)});
                item += named;
            }
            out.errors.insert(out.errors.end(), found.errors.begin(), found.errors.end());
            out.warnings.append(found.warnings);
            continue;
        }
        try {
            for (auto& v : read_virtual_replica(p)) out.sources.push_back({std::move(v.path), v.shift, v.name});
        } catch (const Error& e) {
            out.errors.push_back({p, e.what()});
        }
    }
    drop_duplicate_sources(out);  // where every kind of source meets: each tile read once
    return out;
}

namespace {

// One local path of local_inputs(): the path and what it names.
void add_local_input(const std::string& p, bool allow_lists, std::vector<std::string>& out) {
    if (net::is_url(p)) return;
    out.push_back(p);
    std::error_code ec;
    if (!fs::is_regular_file(p, ec)) return;
    if (is_ept_metadata(p)) {
        out.push_back(fs::path(p).parent_path().empty() ? "." : fs::path(p).parent_path().string());
    } else if (is_virtual_replica(p)) {
        try {
            for (const auto& source : read_virtual_replica(p)) out.push_back(source.path);
        } catch (const Error&) {
            // a malformed manifest is reported when the dataset is opened
        }
    } else if (allow_lists && (is_stac_catalog(p) || (is_tile_list(p) && holds_json_object(p)))) {
        for (const auto& item : read_catalog(p).items) add_local_input(item.href, false, out);
    } else if (allow_lists && is_tile_list(p)) {
        FoundFiles ignored;
        for (const auto& entry : read_tile_list(p, ignored).value_or(std::vector<std::string>{})) {
            add_local_input(entry, false, out);
        }
    }
}

}  // namespace

std::vector<std::string> local_inputs(const std::vector<std::string>& paths) {
    std::vector<std::string> out;
    for (const auto& p : paths) {
        add_local_input(p, true, out);
        if (const std::string replica = replica_or_path(p); replica != p) add_local_input(replica, false, out);
    }
    return out;
}

}  // namespace lidarscout::dataset
