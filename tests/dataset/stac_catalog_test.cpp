// dataset/stac_catalog: QGIS virtual point clouds and STAC ItemCollections, Items, Catalogs and
// Collections as tile lists: hrefs resolved against the document naming them (local or remote),
// links followed once each, what items say kept to place tiles, malformed parts named in a line
// each while the rest is read; a remote catalog's hrefs keep its origin. Opened as a dataset, a
// catalog gives the tiles its folder gives, and a header that disagrees with its item is named.
#include "dataset/stac_catalog.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

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
    ASSERT_EQ(c.errors.size(), 4u);
    const auto has = [&](const std::string& what) {
        return std::any_of(c.errors.begin(), c.errors.end(), [&](const std::string& e) {
            return e.find(what) != std::string::npos && e.find("bad.vpc") != std::string::npos;
        });
    };
    EXPECT_TRUE(has("item 'neg': pc:count"));
    EXPECT_TRUE(has("item 'neg': proj:bbox"));
    EXPECT_TRUE(has("item 'bare' has no data asset"));
    EXPECT_TRUE(has("item #4 is not a STAC item"));
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
    const auto named = std::count_if(lines.begin(), lines.end(), [](const std::string& l) {
        return l.find(kBridgeEast) != std::string::npos && l.find("pc:count 12") != std::string::npos &&
               l.find("disagrees with its catalog item") != std::string::npos;
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

}  // namespace
}  // namespace lidarscout::dataset
