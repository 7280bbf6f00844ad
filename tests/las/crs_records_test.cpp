// The CRS records lidarscout writes read back as the CRS they name (las::parse_geotiff_crs,
// las::parse_wkt_crs; projected and geographic keys), and crs_record_form tells GeoTIFF keys, WKT and
// liblas's WKT copy from each other and from other LASF_Projection and user records.
#include <gtest/gtest.h>

#include <string>

#include "las/crs.hpp"
#include "las/crs_records.hpp"

namespace lidarscout::las {
namespace {

TEST(CrsRecords, GeotiffKeysReadBackAsTheirEpsgCodes) {
    const Vlr keys = geotiff_epsg_vlr(32632);
    EXPECT_TRUE(is_crs_record(keys));
    EXPECT_EQ(keys.data.size(), keys.data_size);
    const Crs crs = parse_geotiff_crs(keys.data, {}, {});
    EXPECT_EQ(crs.source, "geotiff");
    EXPECT_EQ(crs.epsg, 32632);
    EXPECT_FALSE(crs.vertical_epsg);
    EXPECT_EQ(crs.horizontal_unit, LinearUnit::Metre);

    const Crs compound = parse_geotiff_crs(geotiff_epsg_vlr(3089, 5703).data, {}, {});
    EXPECT_EQ(compound.epsg, 3089);
    EXPECT_EQ(compound.vertical_epsg, 5703);
    EXPECT_EQ(compound.horizontal_unit, LinearUnit::UsSurveyFoot);
}

TEST(CrsRecords, WktRecordIsNulTerminated) {
    const std::string wkt = "PROJCS[\"WGS 84 / UTM zone 32N\",AUTHORITY[\"EPSG\",\"32632\"]]";
    const Vlr v = wkt_vlr(wkt);
    EXPECT_TRUE(is_crs_record(v));
    EXPECT_EQ(v.record_id, 2112);
    ASSERT_EQ(v.data.size(), wkt.size() + 1);
    EXPECT_EQ(v.data.back(), 0);
    EXPECT_EQ(std::string(v.data.begin(), v.data.end() - 1), wkt);
}

TEST(CrsRecords, GeographicKeysReadBackInDegrees) {
    const Crs crs = parse_geotiff_crs(geotiff_epsg_vlr(4269, 5703, true).data, {}, {});
    EXPECT_EQ(crs.source, "geotiff");
    EXPECT_TRUE(crs.geographic);
    EXPECT_EQ(crs.epsg, 4269);
    EXPECT_EQ(crs.vertical_epsg, 5703);
    EXPECT_TRUE(crs.warnings.empty());
}

TEST(CrsRecords, FormsOfTheRecords) {
    EXPECT_EQ(crs_record_form(geotiff_epsg_vlr(32632)), CrsForm::GeoTiff);
    EXPECT_EQ(crs_record_form(wkt_vlr("GEOGCS[\"WGS 84\"]")), CrsForm::Wkt);
    Vlr v;
    v.user_id = "liblas";  // what liblas and old LAStools wrote beside the GeoTIFF keys
    v.record_id = 2112;
    EXPECT_EQ(crs_record_form(v), CrsForm::LiblasWkt);
    EXPECT_TRUE(is_crs_record(v));
    v.record_id = 2113;
    EXPECT_EQ(crs_record_form(v), CrsForm::None);
    v.user_id = "LASF_Projection";
    v.record_id = 2111;
    EXPECT_EQ(crs_record_form(v), CrsForm::Wkt);
}

TEST(CrsRecords, OtherRecordsAreNotCrsRecords) {
    Vlr v;
    v.user_id = "LASF_Projection";
    v.record_id = 4;
    EXPECT_FALSE(is_crs_record(v));
    v.user_id = "laszip encoded";
    v.record_id = 34735;
    EXPECT_FALSE(is_crs_record(v));
}

}  // namespace
}  // namespace lidarscout::las
