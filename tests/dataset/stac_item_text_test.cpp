// dataset/stac_item_text: an item of the plain shape read straight from its text; everything else declined
// (nullopt), for the general reader to read and say what it cannot use. (stac_catalog_test's
// APlainItemReadFromItsTextIsWhatTheGeneralReaderMakesOfIt checks the two give one catalog.)
#include "dataset/stac_item_text.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

namespace lidarscout::dataset {
namespace {

const std::vector<std::string> kDropped{"geometry", "bbox", "pc:schemas"};

std::optional<PlainItem> read(const std::string& text) { return read_plain_item(text, kDropped); }

// An item of the plain shape with `properties` (JSON text) and `assets` (JSON text).
std::string item(const std::string& properties, const std::string& assets = R"({"data": {"href": "./a.laz"}})") {
    return R"({"type": "Feature", "id": "a", "geometry": {"type": "Polygon", "coordinates": [[[1, 2], [3, 4]]]},
               "bbox": [1, 2, 3, 4], "properties": )" + properties + R"(, "assets": )" + assets + "}";
}

TEST(StacItemText, APlainItemGivesItsFields) {
    const auto a = read(item(R"({"pc:count": 1867531, "proj:bbox": [5675000.0, 3768732.54, 896.39, 5679999.99,
                                  3769999.99, 1357.39], "proj:epsg": 3089, "pc:schemas": [{"name": "X"}]})"));
    ASSERT_TRUE(a);
    EXPECT_EQ(a->id, "a");
    EXPECT_EQ(a->href, "./a.laz");
    EXPECT_EQ(a->count, 1867531u);
    ASSERT_TRUE(a->bbox);
    EXPECT_EQ((*a->bbox)[0], 5675000.0);
    EXPECT_EQ((*a->bbox)[5], 1357.39);
    EXPECT_EQ(a->crs, "EPSG:3089");
    // 2D boxes, WKT2, no CRS, nulls as absent, no properties, no id, escapes
    const auto b = read(item(R"({"proj:bbox": [1, 2, 3, 4], "proj:wkt2": "PROJCRS[\"x\"]", "pc:count": null})"));
    ASSERT_TRUE(b);
    EXPECT_TRUE(std::isnan((*b->bbox)[2]) && std::isnan((*b->bbox)[5]));
    EXPECT_EQ((*b->bbox)[3], 3);
    EXPECT_EQ(b->crs, "PROJCRS[\"x\"]");
    EXPECT_FALSE(b->count);
    const auto c = read(R"({"type": "Feature", "id": null, "assets": {"x": {"href": "t\u00e9.laz"}}})");
    ASSERT_TRUE(c);
    EXPECT_EQ(c->id, "");
    EXPECT_EQ(c->href, "t\xC3\xA9.laz");
    EXPECT_FALSE(c->bbox || c->count);
    EXPECT_EQ(c->crs, "");
    const auto d = read(item(R"({"proj:epsg": null, "proj:wkt2": ""})"));
    ASSERT_TRUE(d);
    EXPECT_EQ(d->crs, "");
}

// Each of these the general reader says a word about (a warning or a skipped item), chooses between (a key
// written twice, several assets) or reads its own way (PROJJSON): declined.
TEST(StacItemText, AnythingButThePlainShapeIsDeclined) {
    const std::vector<std::string> declined = {
        "", "[]", "\"Feature\"", "{", item("{}") + "x", item("{}").substr(1),
        R"({"type": "Feature", "id": "a", "id": "b", "assets": {"data": {"href": "a.laz"}}})",
        R"({"type": "Feature", "assets": {"data": {"href": "a.laz"}}, "assets": {"data": {"href": "b.laz"}}})",
        R"({"type": "Feature", "assets": {"data": {"href": "a.laz", "href": "b.laz"}}})",
        R"({"type": "Item", "assets": {"data": {"href": "a.laz"}}})",
        R"({"assets": {"data": {"href": "a.laz"}}})",
        R"({"type": "Feature", "id": 7, "assets": {"data": {"href": "a.laz"}}})",
        R"({"type": "Feature"})", R"({"type": "Feature", "assets": {}})",
        R"({"type": "Feature", "assets": {"data": {"href": 7}}})",
        R"({"type": "Feature", "assets": {"data": {"roles": ["data"]}}})",
        R"({"type": "Feature", "assets": {"data": "a.laz"}})",
        R"({"type": "Feature", "assets": {"geometry": {"href": "a.laz"}}})",  // (a key the general reader drops)
        item("{}", R"({"data": {"href": "a.laz"}, "thumb": {"href": "a.png"}})"),
        item("[]"), item(R"({"pc:count": -1})"), item(R"({"pc:count": 1.5})"), item(R"({"pc:count": "lots"})"),
        item(R"({"pc:count": 1e3})"), item(R"({"pc:count": 99999999999999999999999})"),
        item(R"({"pc:count": 1, "pc:count": 2})"), item(R"({"proj:bbox": [1, 2, 3]})"),
        item(R"({"proj:bbox": [3, 2, 1, 4]})"), item(R"({"proj:bbox": [1, 2, "3", 4]})"),
        item(R"({"proj:bbox": {"a": 1}})"), item(R"({"proj:bbox": [1, 2, 1e999, 4]})"),
        item(R"({"proj:epsg": 0})"), item(R"({"proj:epsg": -3089})"), item(R"({"proj:epsg": 2154.0})"),
        item(R"({"proj:epsg": "2154"})"), item(R"({"proj:epsg": 18446744073709551615})"),
        item(R"({"proj:projjson": {"type": "ProjectedCRS"}})"), item(R"({"proj:wkt2": 7})"),
        item(R"({"proj:epsg": 2154, "proj:epsg": 2154})"),
        item(R"({"pc:count": 1})").substr(0, 60) + "\xC3\"}}",  // bad UTF-8
        R"({"type": "Feature", "assets": {"data": {"href": "a\ud800.laz"}}})",  // a lone surrogate
        R"({"type": "Feature", "assets": {"data": {"href": "a.laz"}}, "x": [1 2]})",  // not JSON where unused
        R"({"type": "Feature", "assets": {"data": {"href": "a.laz"}}, "x": 01})",
    };
    for (const auto& text : declined) EXPECT_FALSE(read(text)) << text;
}

}  // namespace
}  // namespace lidarscout::dataset
