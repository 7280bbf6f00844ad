// dataset/stac_catalog: QGIS virtual point clouds and STAC ItemCollections, Items, Catalogs and
// Collections as tile lists: hrefs resolved against the document naming them (local or remote),
// links followed once each, what items say kept to place tiles, malformed parts named in a line
// each while the rest is read; a remote catalog's hrefs keep its origin. Opened as a dataset, a
// catalog gives the tiles its folder gives, and a header that disagrees with its item is named.
// What a new user meets (issue 53), on the BCTS strips: a count that lies is one warning naming the
// item, its catalog and tile, both counts and that the header's is used; a pc:count "lots" is one
// warning and its tile is read (not skipped); an item without an href, and one whose href names no
// file, are each one skipped line naming the item and its catalog. A URL's Content-Type (or first bytes)
// says whether it is a catalog, a tile or a tile list.
#include "dataset/stac_catalog.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "allocation_counter.hpp"
#include "core/thread_pool.hpp"
#include "dataset/dataset.hpp"
#include "dataset/file_search.hpp"
#include "nginx_server.hpp"
#include "temp_dir_fixture.hpp"
#include "test_data.hpp"

namespace lidarscout::dataset {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

const fs::path kIgn = "surveys/ign-lidar-hd-1km";
const char* const kBridgeWest = "test_semis_2023_0299_6802_LA93_IGN69.laz";
const char* const kBridgeEast = "test_semis_2023_0300_6802_LA93_IGN69.laz";

json item(const std::string& id, const std::string& href, json properties = json::object()) {
    return {{"type", "Feature"}, {"stac_version", "1.0.0"}, {"id", id}, {"properties", std::move(properties)},
            {"assets", {{"data", {{"href", href}, {"roles", {"data"}}}}}}, {"links", json::array()}};
}

json collection_of(std::vector<json> items) { return {{"type", "FeatureCollection"}, {"features", std::move(items)}}; }

class StacCatalog : public test::TempDirTest {
protected:
    std::string write(const std::string& name, const json& doc) {
        const fs::path p = dir / name;
        fs::create_directories(p.parent_path());
        std::ofstream(p) << doc.dump(1);
        return p.string();
    }
};

// An item of the plain shape is read straight from its text where threads parse a catalog's items
// (dataset/stac_item_text.hpp), any other by the general reader: on one thread the general reader reads them
// all. Both give one catalog, item for item and line for line, over items plain and not (each thing the general
// reader says a word about or chooses), and the same error where the text stops being JSON.
TEST_F(StacCatalog, APlainItemReadFromItsTextIsWhatTheGeneralReaderMakesOfIt) {
    const std::string geometry = R"("geometry": {"type": "Polygon", "coordinates": [[[1, 2], [3, 4], [1, 2]]]})";
    const auto plain = [&](const std::string& id, const std::string& properties, const std::string& assets) {
        return R"({"type": "Feature", "id": )" + id + ", " + geometry + R"(, "properties": )" + properties +
               R"(, "assets": )" + assets + "}";
    };
    const std::string one = R"({"data": {"href": "./t/a.laz", "roles": ["data"]}})";
    std::vector<std::string> items;
    for (int k = 0; k < 300; ++k) {  // (plain ones, enough for several batches of the threads)
        items.push_back(plain("\"p" + std::to_string(k) + "\"",
                              R"({"pc:count": )" + std::to_string(1000 + k) + R"(, "proj:bbox": [)" +
                                  std::to_string(k) + R"(.5, 2, 3, 1000, 2000, 30], "proj:epsg": 2154})",
                              R"({"data": {"href": "./t/)" + std::to_string(k) + R"(.laz"}})"));
    }
    const std::vector<std::pair<std::string, std::string>> odd = {  // (id, properties) with `one`
        {"null", "{}"}, {"7", "{}"}, {"\"a\"", R"({"pc:count": -1})"}, {"\"b\"", R"({"pc:count": "lots"})"},
        {"\"c\"", R"({"pc:count": 1.5, "proj:bbox": [3, 2, 1, 4]})"}, {"\"d\"", R"({"proj:bbox": [1, 2, 3]})"},
        {"\"e\"", R"({"proj:epsg": 0, "proj:wkt2": "PROJCRS[\"x\"]"})"},
        {"\"f\"", R"({"proj:projjson": {"type": "ProjectedCRS", "name": "x"}})"},
        {"\"g\"", R"({"proj:epsg": "2154", "proj:wkt2": 7})"}, {"\"h\"", R"({"pc:count": 1, "pc:count": 2})"},
        {"\"i\"", "[]"}, {"\"j\"", R"({"proj:bbox": [1, 2, 3, 4], "proj:wkt2": "PROJCRS[\"y\"]"})"},
        {"\"k\"", R"({"proj:epsg": 18446744073709551615})"}, {"\"l\"", "null"}};
    for (const auto& [id, properties] : odd) items.push_back(plain(id, properties, one));
    for (const std::string assets :
         {R"({"data": {"href": "a.laz"}, "thumb": {"href": "a.png", "roles": ["data"]}})", R"({})",
          R"({"data": {"href": 7}})", R"({"data": "a.laz"})", R"({"geometry": {"href": "a.laz"}})",
          R"({"data": {"href": "a.laz", "href": "b.laz"}})", R"({"data": {"href": "../../../x.laz"}})",
          R"({"data": {"href": "ftp://h/x.laz"}})"}) {
        items.push_back(plain("\"m\"", "{}", assets));
    }
    items.push_back(R"({"type": "Item", "assets": {"data": {"href": "a.laz"}}})");
    items.push_back("\"not an item\"");
    items.push_back(R"({"type": "Feature", "id": "n", "id": "o", "assets": {"data": {"href": "a.laz"}}})");
    const auto document = [&](const std::string& last) {
        std::string text = R"({"type": "FeatureCollection", "features": [)";
        for (const auto& i : items) text += i + ",\n";
        return text + last + "]}";
    };
    const auto read_with = [&](unsigned threads, const std::string& text) {
        const fs::path p = dir / "c.vpc";
        std::ofstream(p) << text;
        const unsigned before = ThreadPool::shared_size();
        ThreadPool::set_shared_threads(threads);
        const Catalog c = read_catalog(p.string());
        ThreadPool::set_shared_threads(before);
        return c;
    };
    const auto same = [&](const Catalog& a, const Catalog& b) {
        ASSERT_EQ(a.items.size(), b.items.size());
        for (std::size_t i = 0; i < a.items.size(); ++i) {
            const CatalogItem &x = a.items[i], &y = b.items[i];
            EXPECT_EQ(x.href, y.href);
            EXPECT_EQ(x.id, y.id);
            EXPECT_EQ(std::string(x.document), std::string(y.document));
            EXPECT_EQ(x.count, y.count) << x.id;
            EXPECT_EQ(x.bbox.has_value(), y.bbox.has_value()) << x.id;
            if (x.bbox && y.bbox) {
                for (int k = 0; k < 6; ++k) {
                    EXPECT_TRUE((*x.bbox)[k] == (*y.bbox)[k] || (std::isnan((*x.bbox)[k]) && std::isnan((*y.bbox)[k])));
                }
            }
            EXPECT_EQ(std::string(x.crs), std::string(y.crs)) << x.id;
        }
        EXPECT_EQ(a.errors, b.errors);
        EXPECT_EQ(a.warnings, b.warnings);
    };
    const std::string valid = document(plain("\"z\"", "{}", one));
    const Catalog general = read_with(1, valid), fast = read_with(2, valid);
    same(general, fast);
    // (kept: 300 plain, 14 odd properties, 3 odd assets, the last; said: 6 kept with a warning, 7 left out)
    EXPECT_EQ(general.items.size(), 300u + 14 + 3 + 1 + 1);
    EXPECT_EQ(general.warnings.size(), 6u);
    EXPECT_EQ(general.errors.size(), 7u);
    // and where the text stops being JSON (inside a value the catalog does not use), one error at one place
    const std::string broken =
        document(R"({"type": "Feature", "geometry": [1 2], "assets": {"data": {"href": "a.laz"}}})");
    const Catalog general_broken = read_with(1, broken), fast_broken = read_with(2, broken);
    same(general_broken, fast_broken);
    ASSERT_FALSE(fast_broken.errors.empty());
    EXPECT_NE(fast_broken.errors.back().find("expected"), std::string::npos) << fast_broken.errors.back();
}

TEST_F(StacCatalog, AVirtualPointCloudsItemsResolveAgainstItsFolder) {
    const std::string vpc = write(
        "sub/survey.vpc",
        collection_of({item("a", "./tiles/a.laz",
                            {{"pc:count", 1234}, {"proj:bbox", {1, 2, 3, 4, 5, 6}}, {"proj:epsg", 2154}}),
                       item("b", "../b.laz", {{"proj:bbox", {10, 20, 30, 40}}, {"proj:wkt2", "PROJCRS[...]"}}),
                       item("c", "https://example.com/c.laz")}));
    const Catalog c = read_catalog(vpc);
    EXPECT_TRUE(c.errors.empty()) << c.errors.front();
    ASSERT_EQ(c.items.size(), 3u);
    EXPECT_EQ(c.items[0].href, (dir / "sub/tiles/a.laz").string());
    EXPECT_EQ(c.items[0].count, 1234u);
    EXPECT_EQ(c.items[0].crs, "EPSG:2154");
    ASSERT_TRUE(c.items[0].bbox);
    EXPECT_EQ((*c.items[0].bbox)[2], 3.0);
    EXPECT_EQ((*c.items[0].bbox)[3], 4.0);
    EXPECT_EQ(c.items[1].href, (dir / "b.laz").string());
    EXPECT_FALSE(c.items[1].count);
    ASSERT_TRUE(c.items[1].bbox);
    EXPECT_TRUE(std::isnan((*c.items[1].bbox)[2])) << "a 2D bbox has no heights";
    EXPECT_EQ((*c.items[1].bbox)[4], 40.0);
    EXPECT_EQ(c.items[1].crs, "PROJCRS[...]");
    EXPECT_EQ(c.items[2].href, "https://example.com/c.laz") << "a local catalog may name URLs";
}

// Relative hrefs of every shape resolve as the document's folder joined and normalised says, whatever the
// document's path; the items of a document of several thousand (kept in chunks while it is read) keep their
// order, and an item limit inside such a document keeps exactly that many.
TEST_F(StacCatalog, HrefsOfEveryShapeResolveAndManyItemsKeepTheirOrder) {
    const std::vector<std::string> hrefs = {"a.laz", "./a.laz", "t/a.laz", "./t/./a.laz", "../a.laz", "t//a.laz",
                                            "t/", ".", "..", "./", "t/../a.laz", "...laz", ".hidden/a.laz", "t/."};
    fs::create_directories(dir / "sub"), fs::create_directories(dir / "x/y");  // (named by the paths' "..")
    for (const std::string name : {"sub/survey.vpc", "sub/../other/cat.vpc", "x/./y/../z/c.vpc"}) {
        std::vector<json> items;
        for (std::size_t k = 0; k < hrefs.size(); ++k) items.push_back(item(std::to_string(k), hrefs[k]));
        write(fs::path(name).lexically_normal().string(), collection_of(items));
        const std::string document = (dir / name).string();
        const Catalog c = read_catalog(document);
        ASSERT_EQ(c.items.size(), hrefs.size()) << name;
        for (std::size_t k = 0; k < hrefs.size(); ++k) {
            EXPECT_EQ(c.items[k].href, (fs::path(document).parent_path() / hrefs[k]).lexically_normal().string())
                << name << " " << hrefs[k];
        }
    }
    std::vector<json> many;
    for (int i = 0; i < 10'000; ++i) many.push_back(item("t" + std::to_string(i), "t" + std::to_string(i) + ".laz"));
    const std::string vpc = write("many.vpc", collection_of(many));
    const Catalog all = read_catalog(vpc);
    ASSERT_EQ(all.items.size(), 10'000u);
    for (int i = 0; i < 10'000; i += 997) EXPECT_EQ(all.items[i].id, "t" + std::to_string(i));
    EXPECT_EQ(all.items.back().href, (dir / "t9999.laz").string());
    CatalogLimits limits;
    limits.max_items = 4097;
    const Catalog cut = read_catalog(vpc, limits);
    ASSERT_EQ(cut.items.size(), 4097u);
    EXPECT_EQ(cut.items.back().id, "t4096");
    ASSERT_EQ(cut.errors.size(), 1u);
    EXPECT_NE(cut.errors[0].find("more than 4097 items"), std::string::npos);
}

TEST_F(StacCatalog, CatalogsAndCollectionsAreFollowedOnceEach) {
    write("root.json", {{"type", "Catalog"}, {"id", "root"}, {"links", {{{"rel", "child"}, {"href", "./c1/c.json"}},
                                                                         {{"rel", "self"}, {"href", "./root.json"}}}}});
    const json links = {{{"rel", "item"}, {"href", "i1.json"}},
                        {{"rel", "item"}, {"href", "./i1.json"}},
                        {{"rel", "parent"}, {"href", "../root.json"}},
                        {{"rel", "child"}, {"href", "../root.json"}}};
    write("c1/c.json", {{"type", "Collection"}, {"id", "c1"}, {"links", links}});
    write("c1/i1.json", item("one", "../data/one.laz", {{"pc:count", 5}}));
    const Catalog c = read_catalog((dir / "root.json").string());
    EXPECT_TRUE(c.errors.empty());
    ASSERT_EQ(c.items.size(), 1u) << "the item linked twice, and the cycle back to the root, read once";
    EXPECT_EQ(c.items[0].href, (dir / "data/one.laz").string());
    EXPECT_EQ(c.documents, 3u);
}

TEST_F(StacCatalog, MalformedPartsAreNamedAndTheRestRead) {
    json bad_count = item("neg", "n.laz", {{"pc:count", -5}, {"proj:bbox", {1, 2, 3}}});
    json no_asset = {{"type", "Feature"}, {"stac_version", "1.0.0"}, {"id", "bare"}, {"properties", json::object()}};
    const std::string vpc = write("bad.vpc", collection_of({bad_count, no_asset, item("ok", "ok.laz"), json(7)}));
    const Catalog c = read_catalog(vpc);
    ASSERT_EQ(c.items.size(), 2u) << "an item with a bad field is still a tile; one without an asset is not";
    EXPECT_EQ(c.items[0].id, "neg");
    EXPECT_FALSE(c.items[0].count);
    ASSERT_EQ(c.errors.size(), 2u) << "the items left out";
    ASSERT_EQ(c.warnings.size(), 1u) << "one line for the item kept, whatever of it could not be used";
    const auto has = [&](const std::vector<std::string>& lines, const std::string& what) {
        return std::count_if(lines.begin(), lines.end(), [&](const std::string& e) {
            return e.find(what) != std::string::npos;
        });
    };
    EXPECT_EQ(c.warnings[0], "item 'neg' in " + vpc + ": \"pc:count\" is -5, not a count (a whole number, 0 or "
                             "more); proj:bbox is not 4 or 6 numbers, mins before maxes; the tile's header is read "
                             "instead");
    EXPECT_EQ(has(c.errors, "item 'bare' in " + vpc + ": no data asset with an href"), 1);
    EXPECT_EQ(has(c.errors, "item #4 in " + vpc + ": not a STAC item"), 1);
    const Catalog other = read_catalog(write("other.json", {{"type", "Topology"}}));
    ASSERT_EQ(other.errors.size(), 1u);
    EXPECT_NE(other.errors[0].find("not a STAC catalog"), std::string::npos);
    write("notjson.vpc", json::array());
    EXPECT_EQ(read_catalog((dir / "notjson.vpc").string()).errors.size(), 1u);
}

TEST_F(StacCatalog, LimitsEndAHostileCatalogWithALine) {
    std::vector<json> items;
    for (int i = 0; i < 50; ++i) items.push_back(item("t" + std::to_string(i), "t.laz"));
    const std::string vpc = write("many.vpc", collection_of(items));
    CatalogLimits limits;
    limits.max_items = 10;
    const Catalog c = read_catalog(vpc, limits);
    EXPECT_EQ(c.items.size(), 10u);
    ASSERT_EQ(c.errors.size(), 1u);
    EXPECT_NE(c.errors[0].find("more than 10 items"), std::string::npos);
    // A chain of catalogs deeper than the walk follows.
    for (int i = 0; i < 40; ++i) {
        write("d" + std::to_string(i) + ".json",
              {{"type", "Catalog"}, {"links", {{{"rel", "child"}, {"href", "d" + std::to_string(i + 1) + ".json"}}}}});
    }
    const Catalog deep = read_catalog((dir / "d0.json").string());
    EXPECT_EQ(deep.documents, 33u);
    ASSERT_FALSE(deep.errors.empty());
    EXPECT_NE(deep.errors[0].find("links deep"), std::string::npos);
}

// `n` levels of `open` ... `close` around `inner`, as text (nlohmann would recurse to write it).
std::string nested(int n, const std::string& open, const std::string& inner, const std::string& close) {
    std::string text;
    text.reserve(n * (open.size() + close.size()) + inner.size());
    for (int i = 0; i < n; ++i) text += open;
    text += inner;
    for (int i = 0; i < n; ++i) text += close;
    return text;
}

// A FeatureCollection of `items`, written as text with `extra` (text) spliced into the first item's
// properties.
std::string collection_text(const std::vector<json>& items, const std::string& extra) {
    std::string text = collection_of(items).dump();
    const std::string at = "\"properties\":{";
    const auto pos = text.find(at);
    return text.insert(pos + at.size(), extra + (text[pos + at.size()] == '}' ? "" : ","));
}

TEST_F(StacCatalog, NestingAHundredThousandDeepIsOneLineNotACrash) {
    const json good = item("good", "good.laz");
    for (const std::string& extra : {"\"proj:projjson\":" + nested(100'000, "{\"a\":", "1", "}"),
                                     "\"pc:count\":" + nested(60'000, "[", "1", "]")}) {
        const fs::path p = dir / "deep.vpc";
        std::ofstream(p) << collection_text({item("deep", "d.laz"), good}, extra);
        const Catalog c = read_catalog(p.string());
        ASSERT_EQ(c.errors.size(), 1u);
        EXPECT_NE(c.errors[0].find("deep.vpc: at byte "), std::string::npos) << c.errors[0];
        EXPECT_NE(c.errors[0].find("nested more than the limit of 256 deep"), std::string::npos) << c.errors[0];
        EXPECT_TRUE(c.items.empty()) << "a document that is not read whole gives no items";
    }
    // An item alone, nested deep: the same line.
    std::ofstream(dir / "item.json") << R"({"type": "Feature", "properties": {"proj:projjson": )" +
                                            nested(100'000, "[", "", "]") + "}}";
    const Catalog one = read_catalog((dir / "item.json").string());
    ASSERT_EQ(one.errors.size(), 1u);
    EXPECT_NE(one.errors[0].find("nested more than"), std::string::npos);
}

TEST_F(StacCatalog, AFieldOfTheWrongKindIsItsItemsLineAndTheGoodItemsAreKept) {
    json bad_rel = collection_of({item("ok1", "ok1.laz")});
    json type5 = item("t5", "t5.laz"), id5 = item("x", "id5.laz"), href5 = item("h5", "x");
    type5["type"] = 5;
    id5["id"] = 5;
    href5["assets"]["data"]["href"] = 5;
    json assets5 = item("a5", "a5.laz"), props5 = item("p5", "p5.laz"), count5 = item("c5", "c5.laz");
    assets5["assets"] = 5;
    props5["properties"] = 5;
    count5["properties"]["pc:count"] = "many";
    const std::string vpc = write(
        "typed.vpc", {{"type", "FeatureCollection"},
                      {"features", {type5, id5, href5, assets5, props5, count5, item("ok2", "ok2.laz"), json()}},
                      {"links", {{{"rel", 5}, {"href", "x.json"}}, {{"rel", "next"}, {"href", 7}}}}});
    const Catalog c = read_catalog(vpc);
    std::vector<std::string> ids;
    for (const auto& i : c.items) ids.push_back(i.id);
    EXPECT_EQ(ids, (std::vector<std::string>{"", "p5", "c5", "ok2"})) << "a field that only describes the tile "
                                                                            "gets a line; the tile is kept";
    const auto has = [&](const std::vector<std::string>& lines, const std::string& what) {
        return std::count_if(lines.begin(), lines.end(),
                             [&](const std::string& e) { return e.find(what) != std::string::npos; });
    };
    const std::string in = " in " + vpc + ": ";
    EXPECT_EQ(has(c.errors, "item 't5'" + in + "\"type\" is a number, not a string"), 1);
    EXPECT_EQ(has(c.warnings, "item #2" + in + "\"id\" is a number, not a string; the item is named by its place"), 1);
    EXPECT_EQ(has(c.errors, "item 'h5'" + in + "\"href\" is a number, not a string"), 1);
    EXPECT_EQ(has(c.errors, "item 'a5'" + in + "\"assets\" is a number, not an object"), 1);
    EXPECT_EQ(has(c.warnings, "item 'p5'" + in + "\"properties\" is a number, not an object; the tile's header"), 1);
    EXPECT_EQ(has(c.warnings, "item 'c5'" + in + "\"pc:count\" is a string, not a count (a whole number, 0 or "
                              "more); the tile's header is read instead"), 1);
    EXPECT_EQ(has(c.errors, "item #8" + in + "not a STAC item"), 1);
    EXPECT_EQ(has(c.errors, "link #1: \"rel\" is a number, not a string"), 1);
    EXPECT_EQ(has(c.errors, "a 'next' link without an href"), 1);
    EXPECT_EQ(c.errors.size(), 6u) << "the items left out and the broken links";
    EXPECT_EQ(c.warnings.size(), 3u) << "the items kept, each in one line";
    // A Catalog's links, and a document's type, of the wrong kind.
    write("cat.json", {{"type", "Catalog"},
                       {"links", {{{"rel", 5}}, {{"rel", "child"}, {"href", "sub.vpc"}}, {{"rel", "item"}}}}});
    write("sub.vpc", collection_of({item("s", "s.laz")}));
    const Catalog cat = read_catalog((dir / "cat.json").string());
    ASSERT_EQ(cat.items.size(), 1u);
    EXPECT_EQ(cat.errors.size(), 2u);
    const Catalog typed = read_catalog(write("type.json", {{"type", 5}}));
    ASSERT_EQ(typed.errors.size(), 1u);
    EXPECT_NE(typed.errors[0].find("\"type\" is a number, not a string"), std::string::npos);
    bad_rel["type"] = json::array();
    EXPECT_EQ(read_catalog(write("arr.vpc", bad_rel)).errors.size(), 1u);
}

TEST_F(StacCatalog, LongIdsAndHrefsAreCutInItsLines) {
    const std::string long_id(600'000, 'i'), long_href = "zz:" + std::string(600'000, 'h');
    const std::string vpc =
        write("long.vpc", collection_of({item(long_id, "a.laz", {{"pc:count", -1}}), item("h", long_href),
                                         item("ok", "ok.laz")}));
    const Catalog c = read_catalog(vpc);
    ASSERT_EQ(c.items.size(), 2u);
    ASSERT_EQ(c.errors.size(), 1u);
    ASSERT_EQ(c.warnings.size(), 1u);
    for (const auto& e : {c.errors[0], c.warnings[0]}) EXPECT_LT(e.size(), 700u) << e.substr(0, 300);
    EXPECT_NE(c.warnings[0].find("... (600000 bytes)"), std::string::npos) << "the length is named";
    EXPECT_NE(c.errors[0].find("... (600003 bytes)\" is neither a path"), std::string::npos);
    // A string past the reader's limit (a 200 MB id, here 3 MiB): the document's one line, never the text.
    std::ofstream(dir / "huge.vpc") << collection_of({item(std::string(3u << 20, 'x'), "a.laz")}).dump();
    const Catalog huge = read_catalog((dir / "huge.vpc").string());
    ASSERT_EQ(huge.errors.size(), 1u);
    EXPECT_LT(huge.errors[0].size(), 300u);
    EXPECT_NE(huge.errors[0].find("a string of 3145728 bytes, more than the limit"), std::string::npos);
}

TEST_F(StacCatalog, ItemsAreKeptFromAWholeDocumentWhereverItsTypeIs) {
    // "type" after "features": the items are read and kept once the type is known.
    std::ofstream(dir / "late.vpc") << R"({"features": [)" + item("a", "a.laz").dump() +
                                           R"(], "type": "FeatureCollection"})";
    const Catalog late = read_catalog((dir / "late.vpc").string());
    EXPECT_TRUE(late.errors.empty());
    EXPECT_EQ(late.items.size(), 1u);
    // A document broken after its items gives none of them.
    std::ofstream(dir / "cut.vpc") << R"({"type": "FeatureCollection", "features": [)" + item("a", "a.laz").dump() +
                                          "], ";
    const Catalog cut = read_catalog((dir / "cut.vpc").string());
    EXPECT_TRUE(cut.items.empty());
    ASSERT_EQ(cut.errors.size(), 1u);
    EXPECT_NE(cut.errors[0].find("not JSON"), std::string::npos);
    // Items of a Catalog's features are not tiles.
    write("cat.json", {{"type", "Catalog"}, {"features", {item("a", "a.laz")}}});
    EXPECT_TRUE(read_catalog((dir / "cat.json").string()).items.empty());
}

TEST_F(StacCatalog, AStreamedCatalogHoldsTheItemsKeptNotTheDocument) {
    // Each item carries ~2 KB that is not kept (a detailed footprint), as real catalogs do.
    json footprint = json::array();
    for (int k = 0; k < 100; ++k) footprint.push_back({654321.125 + k, 6543210.25 + k});
    std::string text = R"({"type": "FeatureCollection", "features": [)";
    for (int i = 0; i < 10'000; ++i) {
        json f = item("tile_" + std::to_string(i), "tiles/t" + std::to_string(i) + ".laz",
                      {{"pc:count", 1000 + i}, {"proj:epsg", 2154}});
        f["geometry"] = {{"type", "Polygon"}, {"coordinates", {footprint}}};
        text += (i ? "," : "") + f.dump();
    }
    text += "]}";
    std::ofstream(dir / "big.vpc") << text;
    const test::AllocationCounter counter;
    const Catalog c = read_catalog((dir / "big.vpc").string());
    const std::size_t peak = counter.peak_bytes();
    ASSERT_EQ(c.items.size(), 10'000u);
    EXPECT_TRUE(c.errors.empty());
    EXPECT_LT(peak, text.size() / 3) << "held at once: the items kept, a chunk and one item (document "
                                     << text.size() << " bytes, peak " << peak << ")";
}

// `n` pages of `per_page` items each, page k at pages/pK.json linking the next; the last links to
// `last_next` (none when empty). Returns the first page's path.
std::string write_pages(const fs::path& dir, int n, int per_page, const std::string& last_next = "") {
    for (int k = 0; k < n; ++k) {
        std::vector<json> items;
        for (int i = 0; i < per_page; ++i) {
            const std::string id = "t" + std::to_string(k * per_page + i);
            items.push_back(item(id, id + ".laz"));
        }
        json page = collection_of(items);
        const std::string next = k + 1 < n ? "p" + std::to_string(k + 1) + ".json" : last_next;
        page["links"] = json::array();
        if (!next.empty()) page["links"].push_back({{"rel", "next"}, {"href", next}});
        std::ofstream(dir / ("p" + std::to_string(k) + ".json")) << page.dump();
    }
    return (dir / "p0.json").string();
}

TEST_F(StacCatalog, EveryPageOfASearchIsReadNotOnlyThirtyThree) {
    fs::create_directories(dir / "pages");
    const Catalog c = read_catalog(write_pages(dir / "pages", 200, 10));
    EXPECT_TRUE(c.errors.empty()) << c.errors.front();
    EXPECT_EQ(c.documents, 200u);
    ASSERT_EQ(c.items.size(), 2000u);
    EXPECT_EQ(c.items.back().id, "t1999");
    // Pages are bounded by the catalog's limits all the same: documents, then items.
    CatalogLimits limits;
    limits.max_documents = 50;
    const Catalog capped = read_catalog((dir / "pages" / "p0.json").string(), limits);
    EXPECT_EQ(capped.items.size(), 500u);
    ASSERT_EQ(capped.errors.size(), 1u);
    EXPECT_NE(capped.errors[0].find("more than 50 catalog documents"), std::string::npos) << capped.errors[0];
}

TEST_F(StacCatalog, APageLoopIsOneLineAndThePagesBeforeItAreKept) {
    fs::create_directories(dir / "loop");
    const std::string first = write_pages(dir / "loop", 3, 10, "p1.json");  // page 3 links back to page 2
    const Catalog c = read_catalog(first);
    EXPECT_EQ(c.items.size(), 30u);
    ASSERT_EQ(c.errors.size(), 1u);
    EXPECT_EQ(c.errors[0], first + ": page 3 of " + first + " (" + (dir / "loop" / "p2.json").string() +
                               ") links to " + (dir / "loop" / "p1.json").string() +
                               " as its next page, read already: a page loop; the pages stop there");
    // A server that answers the same page whatever the token: a page that repeats another's items.
    fs::create_directories(dir / "same");
    write_pages(dir / "same", 2, 10, "p2.json");
    for (int k = 2; k < 60; ++k) {
        json again = json::parse(std::ifstream(dir / "same" / "p1.json"));
        again["links"] = {{{"rel", "next"}, {"href", "p" + std::to_string(k + 1) + ".json"}}};
        std::ofstream(dir / "same" / ("p" + std::to_string(k) + ".json")) << again.dump();
    }
    const Catalog same = read_catalog((dir / "same" / "p0.json").string());
    EXPECT_EQ(same.items.size(), 20u);
    EXPECT_EQ(same.documents, 3u);
    ASSERT_EQ(same.errors.size(), 1u);
    EXPECT_NE(same.errors[0].find("page 3 of "), std::string::npos) << same.errors[0];
    EXPECT_NE(same.errors[0].find("repeats the items of page 2: a page loop"), std::string::npos) << same.errors[0];
}

TEST_F(StacCatalog, ACatalogIsKnownByWhatItHoldsNotByItsName) {
    const std::string plain = write("catalog", collection_of({item("a", "a.laz"), item("b", "b.laz")}));
    EXPECT_FALSE(is_stac_catalog(plain));
    EXPECT_TRUE(holds_json_object(plain));
    const FoundFiles found = find_point_cloud_files({plain});
    EXPECT_EQ(found.files, (std::vector<std::string>{(dir / "a.laz").string(), (dir / "b.laz").string()}));
    EXPECT_EQ(found.items.size(), 2u);
    // A tile list keeps its meaning.
    std::ofstream(dir / "a.laz") << "";
    std::ofstream(dir / "list") << "a.laz\n";
    EXPECT_FALSE(holds_json_object((dir / "list").string()));
    EXPECT_EQ(find_point_cloud_files({(dir / "list").string()}).files.size(), 1u);
}

TEST(StacCatalogRemote, ASearchUrlWithoutACatalogsNameOpensAsOne) {
    const auto& server = test::NginxServer::instance();
    // (nginx serves the file "search" whatever the query)
    std::ofstream(server.lists_dir() / "search")
        << collection_of({item("w", std::string("../") + (kIgn / kBridgeWest).string())}).dump();
    const std::string url = server.url("lists/search?collections=ign&bbox=0,0,1,1");
    const FoundFiles found = find_point_cloud_files({url});
    EXPECT_TRUE(found.errors.empty()) << found.errors.front().error;
    EXPECT_EQ(found.files, (std::vector<std::string>{server.url((kIgn / kBridgeWest).string())}));
    // What is not JSON at such a URL keeps today's meaning: a tile list (an HTML page's line too).
    std::ofstream(server.lists_dir() / "items") << "../" << (kIgn / kBridgeEast).string() << "\n";
    const FoundFiles list = find_point_cloud_files({server.url("lists/items?limit=10")});
    EXPECT_EQ(list.files, (std::vector<std::string>{server.url((kIgn / kBridgeEast).string())}));
    std::ofstream(server.lists_dir() / "page") << "<html><body>Not found</body></html>\n";
    const FoundFiles html = find_point_cloud_files({server.url("lists/page?bbox=1,2,3,4")});
    EXPECT_TRUE(html.errors.empty());
    ASSERT_EQ(html.files.size(), 1u) << "a remote tile list's line is a URL: a tile whose reading names it";
    EXPECT_NE(html.files[0].find("Not"), std::string::npos) << html.files[0];
}

// A URL's Content-Type says what it holds before its first bytes do: a catalog whose JSON starts past the
// bytes looked at (blanks first) opens as one when served as application/geo+json, and is a tile list
// (no item) when served as application/octet-stream; a tile at a URL without a .laz name is a tile
// when served as application/vnd.laszip, and by its signature "LASF" when served as octet-stream (it was
// read as a tile list before, and failed).
TEST(StacCatalogRemote, AContentTypeSaysWhatAUrlHolds) {
    const auto& server = test::NginxServer::instance();
    const std::string tile = server.url((kIgn / kBridgeWest).string());
    std::ofstream(server.lists_dir() / "padded") << std::string(300, ' ') << collection_of({item("w", tile)}).dump();
    EXPECT_EQ(content_kind(server.url("typed/json/padded")), ContentKind::catalog);
    const FoundFiles json = find_point_cloud_files({server.url("typed/json/padded")});
    EXPECT_TRUE(json.errors.empty()) << json.errors.front().error;
    EXPECT_EQ(json.files, std::vector<std::string>{tile});
    EXPECT_EQ(json.items.size(), 1u);
    EXPECT_EQ(content_kind(server.url("lists/padded")), ContentKind::other);
    EXPECT_TRUE(find_point_cloud_files({server.url("lists/padded")}).items.empty()) << "read as a catalog";
    fs::remove(server.lists_dir() / "tile");
    fs::create_symlink(test::data_dir() / kIgn / kBridgeWest, server.lists_dir() / "tile");
    for (const std::string url : {server.url("typed/laszip/tile"), server.url("lists/tile")}) {
        EXPECT_EQ(content_kind(url), ContentKind::tile) << url;
        const FoundFiles found = find_point_cloud_files({url});
        EXPECT_TRUE(found.errors.empty()) << found.errors.front().error;
        EXPECT_EQ(found.files, std::vector<std::string>{url});
    }
}

TEST(StacCatalogRemote, ARemoteItemNestedDeepIsOneLine) {
    const auto& server = test::NginxServer::instance();
    std::ofstream(server.lists_dir() / "deep.json")
        << R"({"type": "Feature", "id": "d", "properties": {"proj:projjson": )" +
               nested(100'000, "{\"b\":[", "0", "]}") + "}}";
    const Catalog c = read_catalog(server.url("lists/deep.json"));
    EXPECT_TRUE(c.items.empty());
    ASSERT_EQ(c.errors.size(), 1u);
    EXPECT_NE(c.errors[0].find(server.url("lists/deep.json")), std::string::npos) << c.errors[0];
    EXPECT_NE(c.errors[0].find("nested more than the limit of 256 deep"), std::string::npos) << c.errors[0];
}

// A remote catalog of several read-ahead blocks (dataset/json_file.cpp: 8 MiB each, eight asked at once)
// is read whole and in order: the same items as from the file, each id where it was written.
TEST(StacCatalogRemote, ACatalogOfSeveralReadAheadBlocksIsReadWholeAndInOrder) {
    const auto& server = test::NginxServer::instance();
    std::vector<json> items;
    const std::string filler(1000, 'x');  // (read past, as a catalog's unused properties are)
    for (int i = 0; i < 30'000; ++i) {
        items.push_back(item("t" + std::to_string(i), "../t" + std::to_string(i) + ".laz",
                             {{"pc:count", i + 1}, {"description", filler}}));
    }
    const fs::path local = server.lists_dir() / "big.vpc";
    std::ofstream(local) << collection_of(std::move(items)).dump();
    ASSERT_GT(fs::file_size(local), 3u * (8u << 20)) << "more than three blocks, the last one short";
    const Catalog remote = read_catalog(server.url("lists/big.vpc"));
    ASSERT_EQ(remote.items.size(), 30'000u);
    EXPECT_TRUE(remote.errors.empty()) << remote.errors.front();
    for (std::size_t i = 0; i < remote.items.size(); i += 997) {
        EXPECT_EQ(remote.items[i].id, "t" + std::to_string(i));
        EXPECT_EQ(remote.items[i].count, i + 1);
    }
    EXPECT_EQ(remote.items.back().id, "t29999");
}

TEST(StacCatalogRemote, HrefsResolveAgainstTheUrlAndKeepItsOrigin) {
    const auto& server = test::NginxServer::instance();
    const json vpc = collection_of({item("w", std::string("../") + (kIgn / kBridgeWest).string()),
                                    item("x", "http://198.51.100.7/elsewhere.laz"), item("f", "file:///etc/passwd")});
    std::ofstream(server.lists_dir() / "bridge.vpc") << vpc.dump();
    const Catalog c = read_catalog(server.url("lists/bridge.vpc"));
    ASSERT_EQ(c.items.size(), 1u);
    EXPECT_EQ(c.items[0].href, server.url((kIgn / kBridgeWest).string()));
    ASSERT_EQ(c.errors.size(), 2u) << "another origin and another scheme are refused";
    const auto ds = open_dataset({server.url("lists/bridge.vpc")});
    ASSERT_EQ(ds.tiles.size(), 1u);
    EXPECT_EQ(ds.skipped.size(), 2u);
}

TEST_F(StacCatalog, OpenedAsADatasetItGivesTheFolderTilesAndNamesADisagreement) {
    const fs::path ign = test::data_dir() / kIgn;
    const auto west = open_dataset({(ign / kBridgeWest).string()});
    const auto& h = west.tiles.at(0).tile.header;
    const json right = {{"pc:count", h.point_count},
                        {"proj:bbox", {h.min[0], h.min[1], h.min[2], h.max[0], h.max[1], h.max[2]}},
                        {"proj:epsg", 2154}};
    const json wrong = {{"pc:count", 12}, {"proj:bbox", {0, 0, 0, 10, 10, 10}}};
    const std::string vpc = write("bridge.vpc", collection_of({item("w", (ign / kBridgeWest).string(), right),
                                                                item("e", (ign / kBridgeEast).string(), wrong)}));
    DatasetOptions options;
    std::vector<Bounds> placed;  // before any header is read
    options.sources_found = [&](std::span<const TileSource> sources) {
        for (const auto& s : sources) {
            if (const auto b = s.item ? catalog_footprint(*s.item) : std::nullopt) placed.push_back(*b);
        }
    };
    const auto ds = open_dataset({vpc}, options);
    ASSERT_EQ(ds.tiles.size(), 2u);
    EXPECT_EQ(ds.tiles[0].tile.header.point_count, h.point_count);
    ASSERT_EQ(placed.size(), 2u);
    EXPECT_DOUBLE_EQ(placed[0].min_x, ds.tiles[0].bounds_m.min_x) << "the item placed the tile where it lies";
    EXPECT_DOUBLE_EQ(placed[0].max_y, ds.tiles[0].bounds_m.max_y);
    EXPECT_DOUBLE_EQ(placed[1].max_x, 10.0) << "the wrong item's box, until its header came";
    std::vector<std::string> lines;
    for (const auto& w : ds.warnings) lines.push_back(w.file + ": " + w.message);
    const std::string east = (ign / kBridgeEast).string();
    const auto named = std::count_if(lines.begin(), lines.end(), [&](const std::string& l) {
        return l.find("item 'e' in " + vpc + " disagrees with the header of its tile " + east +
                      ": pc:count: catalog 12, header ") != std::string::npos &&
               l.find("; proj:bbox: catalog x 0.00 .. 10.00, y 0.00 .. 10.00, header x ") != std::string::npos &&
               l.ends_with("; the header's values are used");
    });
    EXPECT_EQ(named, 1) << "the east tile's item is wrong, and only it";
    EXPECT_EQ(std::count_if(lines.begin(), lines.end(),
                            [](const std::string& l) { return l.find(kBridgeWest) != std::string::npos; }),
              0);
    const auto sources = find_tile_sources({vpc}).sources;
    ASSERT_EQ(sources.size(), 2u);
    ASSERT_TRUE(sources[0].item);
    EXPECT_EQ(sources[0].item->count, h.point_count);
    const auto inputs = local_inputs({vpc});
    EXPECT_NE(std::find(inputs.begin(), inputs.end(), (ign / kBridgeEast).string()), inputs.end())
        << "a catalog's local tiles are inputs no output may overwrite";
}

const fs::path kBcts = "surveys/lasr-bcts-strips";
constexpr std::uint64_t kBcts1Points = 531'662;  // bcts_1.laz's header

std::string bcts(const char* name) { return (test::data_dir() / kBcts / name).string(); }

TEST_F(StacCatalog, ACountThatLiesNamesTheItemItsCatalogAndBothCounts) {
    const std::string vpc =
        write("liecount.vpc", collection_of({item("b1", bcts("bcts_1.laz"), {{"pc:count", 1000}})}));
    const auto ds = open_dataset({vpc});
    ASSERT_EQ(ds.tiles.size(), 1u);
    EXPECT_TRUE(ds.skipped.empty());
    EXPECT_EQ(ds.point_count, kBcts1Points) << "the header's count is used";
    ASSERT_EQ(ds.warnings.size(), 1u);
    EXPECT_EQ(ds.warnings[0].message, "item 'b1' in " + vpc + " disagrees with the header of its tile " +
                                          bcts("bcts_1.laz") + ": pc:count: catalog 1000, header 531662; the "
                                          "header's value is used");
    // An item without an id is named by its tile.
    json no_id = item("", bcts("bcts_1.laz"), {{"pc:count", 1000}});
    no_id.erase("id");
    const std::string anonymous = write("anonymous.vpc", collection_of({no_id}));
    const auto again = open_dataset({anonymous});
    ASSERT_EQ(again.warnings.size(), 1u);
    EXPECT_EQ(again.warnings[0].message, "item " + bcts("bcts_1.laz") + " in " + anonymous +
                                             " disagrees with the header of its tile: pc:count: catalog 1000, "
                                             "header 531662; the header's value is used");
}

TEST_F(StacCatalog, ACountOfTheWrongKindIsOneWarningAndItsTileIsRead) {
    const std::string vpc = write("lots.vpc", collection_of({item("b1", bcts("bcts_1.laz"), {{"pc:count", "lots"}}),
                                                             item("b2", bcts("bcts_2.laz"))}));
    const auto ds = open_dataset({vpc});
    EXPECT_EQ(ds.tiles.size(), 2u);
    EXPECT_TRUE(ds.skipped.empty()) << ds.skipped.front().error;
    ASSERT_EQ(ds.warnings.size(), 1u);
    EXPECT_EQ(ds.warnings[0].message, "item 'b1' in " + vpc + ": \"pc:count\" is a string, not a count (a whole "
                                      "number, 0 or more); the tile's header is read instead");
    EXPECT_EQ(ds.warnings[0].file, vpc);
}

TEST_F(StacCatalog, AMissingHrefNamesTheItemAndItsCatalog) {
    json no_href = item("b3", "x");
    no_href["assets"]["data"].erase("href");
    json no_href_nor_id = no_href;
    no_href_nor_id.erase("id");
    const std::string vpc = write("missing.vpc", collection_of({item("b1", bcts("bcts_1.laz")), no_href,
                                                                item("b4", "tiles/gone.laz"), no_href_nor_id}));
    const auto ds = open_dataset({vpc});
    ASSERT_EQ(ds.tiles.size(), 1u);
    std::vector<std::string> lines;
    for (const auto& s : ds.skipped) lines.push_back(s.error);
    const std::string gone = (dir / "tiles/gone.laz").string();
    EXPECT_EQ(lines, (std::vector<std::string>{
                         "item 'b3' in " + vpc + ": no data asset with an href (the tile's path or URL)",
                         "item #4 in " + vpc + ": no data asset with an href (the tile's path or URL)",
                         gone + ": cannot open: No such file or directory (item 'b4' in " + vpc + ")"}));
    EXPECT_TRUE(ds.warnings.empty());
}

}  // namespace
}  // namespace lidarscout::dataset
