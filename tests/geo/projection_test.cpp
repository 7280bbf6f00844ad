// PROJ through geo/projection: units of real CRSs (US survey feet, metres, a compound CRS),
// a round trip between two CRSs back to the same point, bounds in longitude/latitude where the
// surveys lie, and one-line errors for what PROJ cannot use; a compound CRS whose vertical part
// PROJ lacks falls back to its horizontal part with a warning.
#include <gtest/gtest.h>

#include <cmath>

#include "core/error.hpp"
#include "geo/projection.hpp"
#include "geo/crs_definition.hpp"
#include "las/crs.hpp"

namespace lidarscout::geo {
namespace {

TEST(Projection, UnitsOfRealCrs) {
    const CrsInfo ky = crs_info("EPSG:3089");  // Kentucky Single Zone, US survey feet
    EXPECT_NEAR(ky.xy_to_metres, las::kUsSurveyFootMetres, 1e-12);
    EXPECT_FALSE(ky.geographic);
    EXPECT_FALSE(ky.has_vertical);
    EXPECT_NE(ky.name.find("Kentucky"), std::string::npos);
    const CrsInfo lambert = crs_info("EPSG:2154+5720");  // Lambert-93 + NGF-IGN69 height
    EXPECT_TRUE(lambert.has_vertical);
    EXPECT_DOUBLE_EQ(lambert.xy_to_metres, 1.0);
    EXPECT_DOUBLE_EQ(lambert.z_to_metres, 1.0);
    EXPECT_NE(lambert.wkt.find("COMPOUNDCRS"), std::string::npos);
    EXPECT_TRUE(crs_info("EPSG:4326").geographic);
}

TEST(Projection, RoundTripReturnsToThePoint) {
    const CrsTransform there("EPSG:32632", "EPSG:25833"), back("EPSG:25833", "EPSG:32632");
    std::vector<double> x = {497'000.0, 513'456.78}, y = {5'419'000.0, 5'404'321.09}, z = {250.0, 300.0};
    const auto x0 = x, y0 = y;
    there.apply(x, y, z);
    EXPECT_GT(std::abs(x[0] - x0[0]), 100'000.0);  // zone 33 is far from zone 32
    back.apply(x, y, z);
    for (std::size_t i = 0; i < x.size(); ++i) {
        EXPECT_NEAR(x[i], x0[i], 1e-6);
        EXPECT_NEAR(y[i], y0[i], 1e-6);
    }
}

TEST(Projection, HeightsMoveOnlyBetweenCompoundCrss) {
    const CrsTransform dhhn("EPSG:25832+7837", "EPSG:25832+5621");  // DHHN2016 -> EVRF2007 heights
    EXPECT_TRUE(dhhn.transforms_heights());
    double x = 500'000, y = 5'400'000, z = 100;
    dhhn.apply(x, y, z);
    EXPECT_NEAR(z, 100.0264, 0.002);  // the offset in PROJ's database there
    EXPECT_NEAR(x, 500'000, 1e-6);
    EXPECT_TRUE(dhhn.ballpark_at(500'000, 5'400'000, 100).empty());
    EXPECT_FALSE(CrsTransform("EPSG:25832+7837", "EPSG:32632").transforms_heights());
    EXPECT_FALSE(CrsTransform("EPSG:32632", "EPSG:25833").transforms_heights());
}

TEST(Projection, BallparkOperationsAreNamed) {
    // EGM96 -> EGM2008 heights needs a grid PROJ does not have here: a ballpark (no shift).
    const CrsTransform egm("EPSG:32632+5773", "EPSG:32632+3855");
    const std::string op = egm.ballpark_at(500'000, 5'400'000, 100);
    EXPECT_NE(op.find("ballpark"), std::string::npos) << op;
    EXPECT_TRUE(CrsTransform("EPSG:32632", "EPSG:25833").ballpark_at(500'000, 5'400'000, 0).empty());
}

TEST(Projection, LonLatBoundsOfKentucky) {
    // a box of ky-jmo335 in EPSG:3089 feet
    const LonLatBounds b = lonlat_bounds("EPSG:3089", 5'685'000, 3'895'000, 5'700'000, 3'910'000);
    EXPECT_GT(b.west, -84.0);
    EXPECT_LT(b.east, -82.0);
    EXPECT_GT(b.south, 37.0);
    EXPECT_LT(b.north, 38.5);
    EXPECT_LT(b.west, b.east);
    EXPECT_LT(b.south, b.north);
}

// A catalog's thousands of items share a few CRSs: crs_info asks PROJ once a definition (each asking opened its
// database: `lidarscout catalog` of 152,100 tiles spent 280 s there), the same answer every time after.
TEST(Projection, CrsInfoOfOneDefinitionAskedManyTimesAsksProjOnce) {
    const std::size_t before = crs_infos_made();
    const CrsInfo first = crs_info("EPSG:3089");
    CrsInfo last;
    for (int i = 0; i < 1000; ++i) last = crs_info("EPSG:3089");
    EXPECT_LE(crs_infos_made() - before, 1u);
    EXPECT_EQ(first.wkt, last.wkt);
    EXPECT_EQ(first.name, last.name);
    EXPECT_EQ(first.xy_to_metres, last.xy_to_metres);
    (void)crs_info("EPSG:32616");  // the control: another definition is asked
    EXPECT_GE(crs_infos_made() - before, 1u);
    EXPECT_LE(crs_infos_made() - before, 2u);
    EXPECT_THROW(crs_info("EPSG:999999"), Error);  // a failure is not kept
    EXPECT_THROW(crs_info("EPSG:999999"), Error);
}

// A survey's thousands of tiles share a few CRSs: their lon/lat bounds must not each pay for a
// search of PROJ's database (about 6 ms; 2,025 tiles took 12 s of `info` before): counted.
TEST(Projection, LonLatBoundsOfManyTilesInOneCrsShareOneTransform) {
    const std::size_t before = lonlat_transforms_made();
    LonLatBounds first = lonlat_bounds("EPSG:3089", 5'685'000, 3'895'000, 5'700'000, 3'910'000), last;
    for (int i = 0; i < 1000; ++i) last = lonlat_bounds("EPSG:3089", 5'685'000, 3'895'000, 5'700'000, 3'910'000);
    EXPECT_LE(lonlat_transforms_made() - before, 1u);  // one search of PROJ's database, not 1,001
    (void)lonlat_bounds("EPSG:32616", 500'000, 4'000'000, 501'000, 4'001'000);  // the control: another CRS
    EXPECT_LE(lonlat_transforms_made() - before, 2u);
    EXPECT_GE(lonlat_transforms_made() - before, 1u);
    EXPECT_EQ(first.west, last.west);
    EXPECT_EQ(first.north, last.north);
    EXPECT_THROW(lonlat_bounds("EPSG:999999", 0, 0, 1, 1), Error);  // a failure is not kept as a transform
    EXPECT_THROW(lonlat_bounds("EPSG:999999", 0, 0, 1, 1), Error);
}

TEST(Projection, UnusableDefinitionsAreErrors) {
    EXPECT_THROW(crs_info("EPSG:999999"), Error);
    EXPECT_THROW(crs_info("not a crs"), Error);
    EXPECT_THROW(crs_info(""), Error);
    EXPECT_THROW(crs_info("EPSG:5703"), Error);  // vertical only
    const CrsTransform t("EPSG:4326", "EPSG:32632");
    double x = 0, y = 95, z = 0;  // latitude beyond the pole
    EXPECT_THROW(t.apply(x, y, z), Error);
}

// PROJ takes a bare word for the nearest CRS name ("foo" would be Amersfoort): an unknown name
// says so; an exact name still works.
TEST(Projection, UnknownNamesAreUnknownNotTheNearestCrs) {
    try {
        crs_info("foo");
        FAIL() << "foo was taken for a CRS";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("unknown CRS 'foo'"), std::string::npos) << e.what();
    }
    EXPECT_TRUE(crs_info("WGS 84").geographic);
}

las::Crs compound(int horizontal, int vertical) {
    las::Crs crs;
    crs.source = "geotiff";
    crs.epsg = horizontal, crs.vertical_epsg = vertical;
    crs.vertical_unit = las::LinearUnit::UsSurveyFoot;
    return crs;
}

TEST(Projection, CompoundCrsWithAVerticalPartProjLacksFallsBackToItsHorizontalPart) {
    // 4_6_crop.las: 5103 is the code of the NAVD88 datum, not of a vertical CRS
    EXPECT_FALSE(proj_knows_crs("EPSG:2903+5103"));
    auto crs = compound(2903, 5103);
    fall_back_to_horizontal(crs);
    EXPECT_FALSE(crs.vertical_usable);
    EXPECT_EQ(crs_definition(crs), "EPSG:2903");
    ASSERT_EQ(crs.warnings.size(), 1u);
    EXPECT_NE(crs.warnings.begin()->message.find("vertical CRS EPSG:5103"), std::string::npos);
    EXPECT_NE(crs.warnings.begin()->message.find("horizontal CRS EPSG:2903 alone"), std::string::npos);
    EXPECT_EQ(crs.warnings.begin()->message, vertical_fallback_message(crs));
    EXPECT_NO_THROW(lonlat_bounds(crs_definition(crs), 1639600, 1454500, 1639800, 1454700));

    auto known = compound(2903, 6360);  // NAVD88 height (ftUS): PROJ knows it, kept (the control)
    fall_back_to_horizontal(known);
    EXPECT_TRUE(known.vertical_usable);
    EXPECT_EQ(crs_definition(known), "EPSG:2903+6360");
    EXPECT_TRUE(known.warnings.empty());
    EXPECT_EQ(vertical_fallback_message(known), "");

    auto unknown = compound(999999, 5103);  // nothing to fall back to: left for its users to report
    fall_back_to_horizontal(unknown);
    EXPECT_TRUE(unknown.vertical_usable);
    EXPECT_TRUE(unknown.warnings.empty());
}

}  // namespace
}  // namespace lidarscout::geo
