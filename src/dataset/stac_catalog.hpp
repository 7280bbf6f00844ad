// STAC catalogs as tile lists: a QGIS virtual point cloud (.vpc, a STAC ItemCollection of the
// tiles), a STAC ItemCollection or Item, or a STAC Catalog or Collection whose "item" and "child"
// links are followed; local files or URLs. Each item's data asset (the asset whose roles hold
// "data", else the one named "data", else the first) is a tile; its href is resolved against the
// document that names it (a remote document's against its URL, keeping its origin: net/
// origin_policy.hpp). What the item says of its tile -- pc:count, proj:bbox, proj:epsg /
// proj:wkt2 / proj:projjson -- is kept (CatalogItem) so that the tile can be placed before its
// header is read; the header wins where they disagree (dataset.cpp names it in a warning).
//
// A catalog is known by its name (.vpc, .json) or by its content (holds_json_object): a STAC API
// search or items URL opens as one. Bounded and honest: documents are read once each (a cycle of
// links costs nothing more), "child" and "item" links followed at most kMaxDepth deep, an
// ItemCollection's "next" pages followed to the last (a page is no link of depth: a search of any
// number of pages is read whole), a page loop (a next page read already, or a page that repeats
// another's items) one line naming the search and the page, the items before it kept; the
// documents, bytes and items are bounded (CatalogLimits, named in the error when passed). Each
// document goes through the bounded JSON reader (core/json_reader.hpp): its "features" and "links"
// are streamed, their items parsed by every core (--threads) in order, so that memory holds the items kept
// and a few batches being read, whatever the document's size (what an item holds that is not used is read
// past, not built); a document nested too deep, or holding a string too long, is one line. A malformed
// item, field or link (a field of the wrong kind too) gets one line naming the document and the item; the
// rest is read.
// An item that is no tile (no href, not an item) is an error ("item 'ID' in DOC: CAUSE"); a
// field of a tile's item that cannot be used (a pc:count that is a string) is a warning, its tile
// read all the same ("item 'ID' in DOC: CAUSE; the tile's header is read instead").
// Text from the catalog put in a line (ids, hrefs, types) is cut to a couple of hundred characters.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

namespace lidarscout::dataset {

struct Tile;

// Text that many items share, held once (a document's name, a CRS): a pointer's size an item; "" when null.
class SharedText {
public:
    SharedText() = default;
    SharedText(std::string text) : text_(std::make_shared<const std::string>(std::move(text))) {}
    SharedText(const char* text) : SharedText(std::string(text)) {}
    explicit SharedText(std::shared_ptr<const std::string> text) : text_(std::move(text)) {}

    const std::string& str() const { return text_ ? *text_ : none(); }
    operator const std::string&() const { return str(); }
    bool empty() const { return str().empty(); }
    friend bool operator==(const SharedText& a, std::string_view b) { return a.str() == b; }
    friend std::ostream& operator<<(std::ostream& out, const SharedText& t) { return out << t.str(); }

private:
    static const std::string& none() {
        static const std::string none;
        return none;
    }
    std::shared_ptr<const std::string> text_;
};

struct CatalogItem {
    std::string href;                          // the tile: a path or URL, resolved
    std::string id;                            // the item's id ("" when it has none)
    SharedText document;                       // the catalog document that holds it, as shown (cut)
    std::optional<std::uint64_t> count;        // pc:count
    std::optional<std::array<double, 6>> bbox; // proj:bbox: min x, y, z, max x, y, z (z NaN when 2D), CRS units
    SharedText crs;                            // "EPSG:n", WKT2 or PROJJSON text; "" when the item gives none
    // The overview sidecar its catalog names (dataset/overview_sidecar.hpp), resolved; null when none.
    std::shared_ptr<const std::string> overview;
};

// The rel of a catalog's top-level link to its overview sidecar (dataset/overview_sidecar.hpp).
inline constexpr const char* kOverviewRel = "lidarscout:overview";

struct CatalogLimits {
    std::uint64_t max_documents = 100'000;
    std::uint64_t max_items = 4'000'000;
    std::uint64_t max_bytes = 1ull << 30;      // all documents together
    // One document may be all of them: it is streamed (each item kept as it is read, what the catalog does
    // not use read past), never held whole, so its size costs time, not memory. A country's VPC is one
    // document: 152,100 items of about 1.6 KB each (lidarscout catalog's) make 250 MB.
    std::uint64_t max_document_bytes = 1ull << 30;
};

struct Catalog {
    std::vector<CatalogItem> items;   // in document order, links followed breadth-first
    std::vector<std::string> errors;    // one line per document, item or link that could not be used
    std::vector<std::string> warnings;  // one line per item kept though some of it could not be used
    std::uint64_t documents = 0;      // documents read
    std::string overview;  // the first ItemCollection's kOverviewRel link, resolved ("" when none)
};

// True for a path or URL whose file name ends in .vpc or .json (case-insensitive) and is not EPT
// metadata (ept.json, entwine.json): what is read as a STAC catalog.
bool is_stac_catalog(const std::string& path);

// What a file or URL holds, told before it is read as one thing or another.
enum class ContentKind { catalog, tile, other };

// A remote file's Content-Type when it says (application/json, application/geo+json or another type ending
// in +json: a catalog; application/vnd.laszip or application/vnd.las: a tile), else its first bytes (a JSON
// object, its first byte other than white space after a UTF-8 byte order mark '{': a catalog; the LAS
// signature "LASF": a tile). What makes a catalog of a STAC API search (.../search?collections=...&bbox=...)
// or items endpoint (.../collections/C/items), or a catalog served without a .json name, and a tile of a
// URL without a .las/.laz name. Reads its first bytes (a remote file's edge and headers, as it is opened);
// `other` when it cannot be opened (its reading as a tile or list then says why).
ContentKind content_kind(const std::string& path);

// content_kind(path) == ContentKind::catalog.
bool holds_json_object(const std::string& path);

// Called after each document of a catalog that gave items (a STAC API search's page): the catalog read so far,
// where the document's items start in it, and whether documents remain to be read (further pages, links).
using CatalogItemsRead = std::function<void(const Catalog& so_far, std::size_t first_item, bool more)>;

// Called with the overview sidecar a catalog's document names (resolved) as soon as its link is read: before its
// items where the link comes first (a reader that fetches the sidecar while they are read). Once a catalog.
using SidecarNamed = std::function<void(const std::string& sidecar)>;

// The items of the catalog at `path` and of every document it links, with what could not be used;
// `items_read` sees them as each document is read (a reader that opens from the first pages of a search).
Catalog read_catalog(const std::string& path, const CatalogLimits& limits = {},
                     const CatalogItemsRead& items_read = {}, const SidecarNamed& sidecar_named = {});

// "item 'ID' in DOCUMENT" (the document as shown), or "item HREF in DOCUMENT" for an item without id.
std::string item_name(const CatalogItem& item);

// The line saying how what the item says disagrees with what the tile's header says, naming the item,
// its catalog and tile, each value on both sides and that the header's is used ("" when they agree):
// a count, bounds (beyond 1% of the extent plus a millimetre) or EPSG code that differs. `bounds` in the
// header's units.
std::string item_disagreement(const CatalogItem& item, const Tile& tile);

}  // namespace lidarscout::dataset
