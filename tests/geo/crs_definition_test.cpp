// crs_definition: EPSG codes (with the vertical one as a compound "h+v"), WKT otherwise,
// nothing without a horizontal CRS; epsg_of_definition reads back only "EPSG:n", epsg_codes_of_definition
// also "EPSG:h+v".
#include <gtest/gtest.h>

#include <utility>

#include "geo/crs_definition.hpp"

namespace lidarscout::geo {
namespace {

TEST(CrsDefinition, EpsgCompoundWktAndNone) {
    las::Crs c;
    EXPECT_EQ(crs_definition(c), "");
    c.vertical_epsg = 5703;
    EXPECT_EQ(crs_definition(c), "");  // a vertical CRS alone places nothing
    c.wkt = "PROJCS[\"x\"]";
    EXPECT_EQ(crs_definition(c), "PROJCS[\"x\"]");
    c.epsg = 3089;
    EXPECT_EQ(crs_definition(c), "EPSG:3089+5703");
    c.vertical_epsg.reset();
    EXPECT_EQ(crs_definition(c), "EPSG:3089");
}

TEST(CrsDefinition, EpsgOfDefinition) {
    EXPECT_EQ(epsg_of_definition("EPSG:2154"), 2154);
    EXPECT_EQ(epsg_of_definition("epsg:32632"), 32632);
    EXPECT_EQ(epsg_of_definition("EPSG:2154+5720"), 0);
    EXPECT_EQ(epsg_of_definition("EPSG:"), 0);
    EXPECT_EQ(epsg_of_definition("PROJCS[...]"), 0);
}

TEST(CrsDefinition, EpsgCodesOfDefinition) {
    const auto codes = [](const char* d) {
        const EpsgCodes c = epsg_codes_of_definition(d);
        return std::pair{c.horizontal, c.vertical};
    };
    EXPECT_EQ(codes("EPSG:2154"), std::pair(2154, 0));
    EXPECT_EQ(codes("epsg:2154+5720"), std::pair(2154, 5720));
    EXPECT_EQ(codes("EPSG:2154+"), std::pair(0, 0));
    EXPECT_EQ(codes("EPSG:2154+x"), std::pair(0, 0));
    EXPECT_EQ(codes("EPSG:2154 "), std::pair(0, 0));
    EXPECT_EQ(codes("PROJCS[...]"), std::pair(0, 0));
}

}  // namespace
}  // namespace lidarscout::geo
