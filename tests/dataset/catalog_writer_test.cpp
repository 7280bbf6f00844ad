// dataset/catalog_writer: a dataset written as a virtual point cloud opens again with the same
// tiles, counts and bounds (and no disagreement), carries the fields the STAC item and
// ItemCollection schemas require and those QGIS and PDAL wrench read, names local tiles relative
// to its folder, and refuses a virtual replica (its tiles are not files).
#include "dataset/catalog_writer.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "core/error.hpp"
#include "dataset/stac_catalog.hpp"
#include "dataset/virtual_replica.hpp"
#include "temp_dir_fixture.hpp"
#include "test_data.hpp"

namespace lidarscout::dataset {
namespace {

namespace fs = std::filesystem;

class CatalogWriter : public test::TempDirTest {};

TEST_F(CatalogWriter, AWrittenCatalogOpensAgainWithTheSameTiles) {
    const auto ds = open_dataset({(test::surveys_dir() / "ign-lidar-hd-1km").string()});
    ASSERT_EQ(ds.tiles.size(), 7u);
    const std::string vpc = path("ign.vpc");
    const auto r = write_catalog(ds, vpc);
    EXPECT_EQ(r.items, 7u);
    EXPECT_EQ(r.without_crs, 0u);
    const auto again = open_dataset({vpc});
    ASSERT_EQ(again.tiles.size(), ds.tiles.size());
    EXPECT_EQ(again.warnings.size(), ds.warnings.size()) << "no header disagrees with its item";
    for (std::size_t i = 0; i < ds.tiles.size(); ++i) {
        EXPECT_EQ(fs::canonical(again.tiles[i].tile.path()), fs::canonical(ds.tiles[i].tile.path()));
        EXPECT_EQ(again.tiles[i].tile.header.point_count, ds.tiles[i].tile.header.point_count);
        EXPECT_EQ(again.tiles[i].bounds_m.min_x, ds.tiles[i].bounds_m.min_x);
        EXPECT_EQ(again.tiles[i].bounds_m.max_y, ds.tiles[i].bounds_m.max_y);
    }
    EXPECT_EQ(again.point_count, ds.point_count);
}

TEST_F(CatalogWriter, ItCarriesTheFieldsStacAndQgisRead) {
    const fs::path ign = test::surveys_dir() / "ign-lidar-hd-1km";
    const auto ds = open_dataset({(ign / "test_semis_2023_0299_6802_LA93_IGN69.laz").string()});
    const std::string vpc = path("one.vpc");
    write_catalog(ds, vpc);
    const auto doc = nlohmann::json::parse(std::ifstream(vpc));
    EXPECT_EQ(doc.at("type"), "FeatureCollection");
    ASSERT_EQ(doc.at("features").size(), 1u);
    const auto& f = doc["features"][0];
    for (const char* k : {"type", "stac_version", "id", "geometry", "bbox", "properties", "links", "assets"}) {
        EXPECT_TRUE(f.contains(k)) << k;  // STAC item, required
    }
    EXPECT_EQ(f.at("type"), "Feature");
    EXPECT_EQ(f.at("stac_version"), "1.0.0");
    EXPECT_EQ(f.at("id"), "test_semis_2023_0299_6802_LA93_IGN69");
    const auto& p = f.at("properties");
    EXPECT_EQ(p.at("datetime"), "2025-04-10T00:00:00Z") << "the header's creation day 100 of 2025";
    EXPECT_EQ(p.at("pc:count"), 278'810);
    EXPECT_EQ(p.at("pc:type"), "lidar");
    EXPECT_EQ(p.at("pc:encoding"), "laszip");
    EXPECT_FALSE(p.at("pc:schemas").empty());
    EXPECT_EQ(p.at("proj:epsg"), 2154);
    EXPECT_FALSE(p.contains("proj:wkt2")) << "EPSG:2154 says all of it";
    ASSERT_EQ(p.at("proj:bbox").size(), 6u);
    EXPECT_EQ(p.at("proj:bbox")[0], ds.tiles[0].tile.header.min[0]);
    EXPECT_FALSE(p.contains("proj:geometry")) << "proj:bbox's rectangle again";
    // GeoJSON in WGS 84: the tile lies in France.
    EXPECT_EQ(f.at("geometry").at("type"), "Polygon");
    EXPECT_GT(f.at("bbox")[0].get<double>(), -6.0);
    EXPECT_LT(f.at("bbox")[3].get<double>(), 10.0);
    EXPECT_GT(f.at("bbox")[1].get<double>(), 41.0);
    const auto& data = f.at("assets").at("data");
    EXPECT_EQ(data.at("roles"), nlohmann::json::array({"data"}));
    const std::string href = data.at("href");
    EXPECT_TRUE(href.rfind("./", 0) == 0 || href.rfind("../", 0) == 0) << href << ": relative to the catalog";
    EXPECT_EQ(fs::canonical(fs::path(vpc).parent_path() / href), fs::canonical(ds.tiles[0].tile.path()));
}

// A country's catalog (152,100 items) must stay small enough to read in a second: an EPSG code that
// says the whole CRS is not repeated as 1.9 KB of WKT, and each item is one compact line.
TEST_F(CatalogWriter, AnEpsgCodeThatSaysTheWholeCrsIsWrittenAloneAndEachItemIsOneLine) {
    const auto ds = open_dataset({(test::surveys_dir() / "ky-jmo335-eastern-kentucky").string()});
    ASSERT_EQ(ds.tiles.size(), 9u);
    const std::string vpc = path("ky.vpc");
    write_catalog(ds, vpc);
    std::ifstream in(vpc);
    std::vector<std::string> lines;
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    ASSERT_EQ(lines.size(), 9u + 2u) << "a head line, one line per item, a tail line";
    for (std::size_t i = 1; i <= 9; ++i) {
        const std::string line = lines[i].substr(0, lines[i].size() - (i < 9 ? 1 : 0));  // (the comma)
        const auto item = nlohmann::json::parse(line);
        const auto& p = item.at("properties");
        EXPECT_EQ(p.at("proj:epsg"), 3089);
        EXPECT_FALSE(p.contains("proj:wkt2")) << "EPSG:3089 says all of it";
        EXPECT_LT(line.size(), 1'800u) << line;  // (pc:schemas, required, is 640 of them)
    }
    const auto again = open_dataset({vpc});
    ASSERT_EQ(again.tiles.size(), 9u);
    EXPECT_EQ(again.frame.crs, ds.frame.crs);
    EXPECT_EQ(again.point_count, ds.point_count);
}

// A compound CRS (NAD83 / Oregon LCC + NAVD88 heights in US feet) has no one EPSG code: its item carries
// the WKT, which the catalog reads back whole (heights' unit included), not the horizontal code alone.
TEST_F(CatalogWriter, ACompoundCrsIsWrittenAsWktAndReadBackWhole) {
    const auto tile = test::formats_dir() / "PDAL__PDAL" / "test__data__copc__1.2-with-color.copc.laz";
    const auto ds = open_dataset({tile.string()});
    ASSERT_EQ(ds.tiles.size(), 1u);
    const std::string vpc = path("compound.vpc");
    write_catalog(ds, vpc);
    const auto doc = nlohmann::json::parse(std::ifstream(vpc));
    const auto& p = doc.at("features").at(0).at("properties");
    EXPECT_FALSE(p.contains("proj:epsg")) << "EPSG:2991 alone would lose NAVD88";
    EXPECT_NE(p.at("proj:wkt2").get<std::string>().find("NAVD88"), std::string::npos);
    const auto catalog = read_catalog(vpc);
    ASSERT_EQ(catalog.items.size(), 1u);
    EXPECT_NE(catalog.items[0].crs.str().find("NAVD88"), std::string::npos) << catalog.items[0].crs;
}

TEST_F(CatalogWriter, AVirtualReplicaIsRefusedAndNothingWritten) {
    const auto src = (test::surveys_dir() / "ky-woodford-county").string();
    std::string out;
    ASSERT_EQ(test::run_command(std::string(LIDARSCOUT_CLI) + " synth replicate " + src + " --grid 2x1 --virtual -o " +
                                    path("rep") + " >/dev/null 2>&1", out), 0);
    const auto ds = open_dataset({path("rep")});
    ASSERT_EQ(ds.tiles.size(), 2u);
    EXPECT_THROW(write_catalog(ds, path("rep.vpc")), Error);
    EXPECT_FALSE(fs::exists(path("rep.vpc")));
}

}  // namespace
}  // namespace lidarscout::dataset
