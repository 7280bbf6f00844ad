// pipelines::write_crs and keep_crs: the records of a written file state one CRS in the form its point
// format expects. bcts_2.laz (GeoTIFF keys of EPSG:3005+5713 beside liblas's WKT copy) keeps its keys
// alone; its CRS for point format 6 becomes one WKT record; a CRS in degrees gets geographic GeoTIFF
// keys; a CRS without EPSG code cannot be GeoTIFF keys on LAS 1.2 (refused, records untouched);
// GeoTIFF keys without EPSG code (autzen_trim.las) keep the WKT that names their CRS.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "dataset/tile.hpp"
#include "geo/projection.hpp"
#include "io/file.hpp"
#include "las/crs.hpp"
#include "las/crs_records.hpp"
#include "pipelines/output_records.hpp"
#include "test_data.hpp"

namespace lidarscout::pipelines {
namespace {

struct Records {
    las::Header header;
    std::vector<las::Vlr> vlrs, evlrs;
    las::Crs crs;
};

Records records_of(const std::string& path) {
    const dataset::Tile t = dataset::read_tile(io::File::open(path));
    return {t.header, t.vlrs(), t.evlrs(), t.crs()};
}

Records bcts_2() { return records_of((test::surveys_dir() / "lasr-bcts-strips" / "bcts_2.laz").string()); }

// The forms of the CRS records among `vlrs`, in order.
std::vector<las::CrsForm> forms(const std::vector<las::Vlr>& vlrs) {
    std::vector<las::CrsForm> out;
    for (const auto& v : vlrs) {
        if (las::is_crs_record(v)) out.push_back(las::crs_record_form(v));
    }
    return out;
}

const las::Vlr& only_crs_record(const std::vector<las::Vlr>& vlrs) {
    const auto it = std::find_if(vlrs.begin(), vlrs.end(), las::is_crs_record);
    EXPECT_EQ(std::count_if(vlrs.begin(), vlrs.end(), las::is_crs_record), 1);
    return *it;
}

TEST(OutputRecords, TheSourcesOtherFormIsDropped) {
    Records r = bcts_2();
    ASSERT_EQ(r.crs.source, "geotiff");
    ASSERT_EQ(forms(r.vlrs), (std::vector{las::CrsForm::GeoTiff, las::CrsForm::GeoTiff, las::CrsForm::LiblasWkt}));
    const auto notes = keep_crs(r.header, r.vlrs, r.evlrs, r.crs, "clip");
    EXPECT_EQ(forms(r.vlrs), (std::vector{las::CrsForm::GeoTiff, las::CrsForm::GeoTiff}));  // 34735 + its ASCII
    ASSERT_EQ(notes.size(), 1u);
    EXPECT_NE(notes[0].find("dropped the liblas 2112 VLR: the CRS is stated once, by the GeoTIFF keys "
                            "(EPSG:3005+5713)"), std::string::npos) << notes[0];
    EXPECT_EQ(r.header.global_encoding & 0x10, 0);
    EXPECT_TRUE(keep_crs(r.header, r.vlrs, r.evlrs, r.crs, "clip").empty());  // already so: nothing to say
}

TEST(OutputRecords, UserDefinedKeysKeepTheWktThatNamesThem) {
    // autzen_trim.las: GeoTIFF keys of a Lambert conic without EPSG code, its WKT, liblas's copy of it.
    Records r = records_of((test::formats_dir() / "PDAL__PDAL/test__data__las__autzen_trim.las").string());
    ASSERT_EQ(r.crs.source, "geotiff");
    ASSERT_FALSE(r.crs.epsg);
    const auto notes = keep_crs(r.header, r.vlrs, r.evlrs, r.crs, "clip");
    EXPECT_EQ(forms(r.vlrs), (std::vector{las::CrsForm::GeoTiff, las::CrsForm::GeoTiff, las::CrsForm::GeoTiff,
                                          las::CrsForm::Wkt}));
    ASSERT_EQ(notes.size(), 1u);
    EXPECT_NE(notes[0].find("dropped the liblas 2112 VLR"), std::string::npos) << notes[0];
}

TEST(OutputRecords, FormatsSixToTenGetOneWktRecord) {
    Records r = bcts_2();
    r.header.point_format = 6;
    r.header.version_minor = 4;
    const auto notes = keep_crs(r.header, r.vlrs, r.evlrs, r.crs, "convert");
    ASSERT_EQ(notes.size(), 1u);
    EXPECT_NE(notes[0].find("GeoTIFF keys replaced by the WKT of EPSG:3005+5713"), std::string::npos) << notes[0];
    const las::Vlr& wkt = only_crs_record(r.vlrs);
    EXPECT_EQ(las::crs_record_form(wkt), las::CrsForm::Wkt);
    EXPECT_EQ(r.header.global_encoding & 0x10, 0x10);
    const las::Crs back = las::parse_wkt_crs(std::string(wkt.data.begin(), wkt.data.end() - 1));
    EXPECT_EQ(back.epsg, 3005);
    EXPECT_EQ(back.vertical_epsg, 5713);
}

TEST(OutputRecords, ANewCrsReplacesEveryRecord) {
    Records r = bcts_2();
    write_crs(r.header, r.vlrs, r.evlrs, "EPSG:32610", "clip");
    const las::Vlr& keys = only_crs_record(r.vlrs);
    const las::Crs utm = las::parse_geotiff_crs(keys.data, {}, {});
    EXPECT_EQ(utm.epsg, 32610);
    EXPECT_FALSE(utm.vertical_epsg);
    EXPECT_FALSE(utm.geographic);

    write_crs(r.header, r.vlrs, r.evlrs, "EPSG:4326", "clip");  // degrees: GTModelType geographic
    const las::Crs lonlat = las::parse_geotiff_crs(only_crs_record(r.vlrs).data, {}, {});
    EXPECT_EQ(lonlat.epsg, 4326);
    EXPECT_TRUE(lonlat.geographic);
    EXPECT_TRUE(lonlat.warnings.empty()) << lonlat.warnings.messages().front();
}

TEST(OutputRecords, ACrsWithoutEpsgCodeIsRefusedOnOldFormatsAndWktOnLas14) {
    Records r = bcts_2();
    const std::string wkt = geo::crs_wkt1("EPSG:3005");  // a definition that is WKT, no "EPSG:n"
    try {
        write_crs(r.header, r.vlrs, r.evlrs, wkt, "clip");  // LAS 1.2, format 1
        FAIL() << "a WKT-only CRS was written as GeoTIFF keys";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("only by an EPSG code"), std::string::npos) << e.what();
    }
    EXPECT_EQ(forms(r.vlrs).size(), 3u);  // untouched
    r.header.version_minor = 4;
    write_crs(r.header, r.vlrs, r.evlrs, wkt, "clip");
    EXPECT_EQ(las::crs_record_form(only_crs_record(r.vlrs)), las::CrsForm::Wkt);
    EXPECT_EQ(r.header.global_encoding & 0x10, 0x10);
}

}  // namespace
}  // namespace lidarscout::pipelines
