// CRS and units: real survey tiles (Kentucky ftUS, IGN Lambert-93, ISPRS UTM 32N), the WKT
// variants of the format corpus, files without a CRS, and hand-built malformed records.
#include "las/crs.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "io/file.hpp"
#include "las/header.hpp"
#include "las/vlr.hpp"
#include "test_data.hpp"

namespace lidarscout::las {
namespace {

namespace fs = std::filesystem;
using test::formats_dir;
using test::surveys_dir;

constexpr std::uint16_t kWktBit = 0x10;  // global encoding bit 4

Crs crs_of(const fs::path& path) {
    auto file = io::File::open(path.string());
    const Header h = read_header(file);
    return read_crs(read_vlrs(file, h), read_evlrs(file, h), file, (h.global_encoding & kWktBit) != 0);
}

std::vector<fs::path> laz_files(const fs::path& dir) {
    std::vector<fs::path> out;
    for (const auto& e : fs::directory_iterator(dir)) {
        if (e.path().extension() == ".laz") out.push_back(e.path());
    }
    std::sort(out.begin(), out.end());
    return out;
}

std::string joined(const Diagnostics& v) {
    std::string s;
    for (const auto& w : v) s += w.message + "\n";
    return s;
}

bool any_warning_contains(const Crs& c, const std::string& needle) {
    for (const auto& w : c.warnings) {
        if (w.message.find(needle) != std::string::npos) return true;
    }
    return false;
}

TEST(Crs, KentuckySurveysAreUsSurveyFeet) {
    std::size_t files = 0;
    for (const auto& dir : fs::directory_iterator(surveys_dir())) {
        if (dir.path().filename().string().rfind("ky-", 0) != 0) continue;
        for (const auto& path : laz_files(dir.path())) {
            SCOPED_TRACE(path.string());
            const Crs c = crs_of(path);
            EXPECT_EQ(c.source, "geotiff");
            EXPECT_EQ(c.epsg, 3089);
            EXPECT_EQ(c.name, "NAD83 / Kentucky Single Zone (ftUS)");
            EXPECT_FALSE(c.geographic);
            EXPECT_EQ(c.horizontal_unit, LinearUnit::UsSurveyFoot);
            EXPECT_EQ(c.vertical_unit, LinearUnit::UsSurveyFoot);
            EXPECT_DOUBLE_EQ(c.horizontal_to_metres, 1200.0 / 3937.0);
            EXPECT_DOUBLE_EQ(c.vertical_to_metres, 1200.0 / 3937.0);
            EXPECT_DOUBLE_EQ(c.z_to_metres(), 1200.0 / 3937.0);
            EXPECT_STREQ(unit_name(c.horizontal_unit), "us_survey_foot");
            EXPECT_TRUE(c.warnings.empty()) << joined(c.warnings);
            ++files;
        }
    }
    EXPECT_EQ(files, 11u);  // 9 eastern Kentucky + Red River Gorge + Woodford County
}

TEST(Crs, IgnTilesAreLambert93Metres) {
    const auto files = laz_files(surveys_dir() / "ign-lidar-hd-1km");
    ASSERT_GE(files.size(), 5u);
    for (const auto& path : files) {
        SCOPED_TRACE(path.string());
        const Crs c = crs_of(path);
        EXPECT_EQ(c.source, "wkt");
        EXPECT_EQ(c.epsg, 2154);
        EXPECT_EQ(c.horizontal_unit, LinearUnit::Metre);
        EXPECT_DOUBLE_EQ(c.horizontal_to_metres, 1.0);
        EXPECT_EQ(c.vertical_unit, LinearUnit::Unknown);  // no vertical CRS in the WKT
        EXPECT_TRUE(std::isnan(c.vertical_to_metres));
        EXPECT_DOUBLE_EQ(c.z_to_metres(), 1.0);           // falls back to the horizontal unit
        EXPECT_NE(c.wkt.find("Lambert"), std::string::npos);
        EXPECT_TRUE(c.warnings.empty()) << joined(c.warnings);
    }
}

TEST(Crs, IsprsSitesAreUtm32North) {
    const auto files = laz_files(surveys_dir() / "isprs-filter-test-sites");
    ASSERT_EQ(files.size(), 8u);
    for (const auto& path : files) {
        SCOPED_TRACE(path.string());
        const Crs c = crs_of(path);
        EXPECT_EQ(c.source, "geotiff");
        EXPECT_EQ(c.epsg, 32632);
        EXPECT_EQ(c.horizontal_unit, LinearUnit::Metre);
        EXPECT_EQ(c.vertical_unit, LinearUnit::Metre);
        EXPECT_TRUE(c.warnings.empty()) << joined(c.warnings);
    }
}

TEST(Crs, RaleighEptReportsItsWrongTag) {
    // Tagged NAD83 / North Carolina (ftUS) although x/y are metres: we report the tag.
    const Crs c = crs_of(surveys_dir() / "nc-raleigh-ept" / "ept" / "0-0-0-0.laz");
    EXPECT_EQ(c.epsg, 2264);
    EXPECT_EQ(c.horizontal_unit, LinearUnit::UsSurveyFoot);
    EXPECT_EQ(c.vertical_unit, LinearUnit::Unknown);
}

struct WktCase {
    const char* file;
    std::optional<int> epsg, vertical_epsg;
    bool geographic;
    LinearUnit horizontal, vertical;
};

TEST(Crs, WktVariantsOfTheCorpus) {
    const WktCase cases[] = {
        // WKT1 COMPD_CS: projected metres + NAVD88 height (ftUS)
        {"PDAL__PDAL/test__data__copc__1.2-with-color.copc.laz", 2991, 6360, false, LinearUnit::Metre,
         LinearUnit::UsSurveyFoot},
        // WKT1 COMPD_CS: international feet horizontally, US survey feet vertically
        {"gadomski__las-rs/tests__data__autzen.copc.laz", 2992, 6360, false, LinearUnit::InternationalFoot,
         LinearUnit::UsSurveyFoot},
        // WKT2 PROJCRS with ID["EPSG",...] and a LENGTHUNIT on the CRS
        {"PDAL__PDAL/test__data__laz__las_with_several_extra_byte_bloc.laz", 2154, std::nullopt, false,
         LinearUnit::Metre, LinearUnit::Unknown},
        // WKT2 pretty-printed, units only on the axes
        {"laspy__laspy/tests__data__fullwave.laz", 32723, std::nullopt, false, LinearUnit::Metre, LinearUnit::Unknown},
        // WKT1 GEOGCS: degrees, no linear unit
        {"PDAL__PDAL/test__data__tindex__autzen_clip_4326.copc.laz", 4326, std::nullopt, true, LinearUnit::Unknown,
         LinearUnit::Unknown},
        // WKT1 GEOCCS without an authority
        {"PDAL__PDAL/test__data__copc__lone-star.copc.laz", std::nullopt, std::nullopt, false, LinearUnit::Metre,
         LinearUnit::Unknown},
        // ESRI-style WKT1 in international feet, no authority
        {"PDAL__PDAL/test__data__las__autzen_trim_7.las", std::nullopt, std::nullopt, false,
         LinearUnit::InternationalFoot, LinearUnit::Unknown},
        // COMPD_CS without authorities, "Meter"
        {"hobuinc__untwine/test__data__eb.laz", std::nullopt, std::nullopt, false, LinearUnit::Metre,
         LinearUnit::Metre},
    };
    for (const auto& k : cases) {
        SCOPED_TRACE(k.file);
        const Crs c = crs_of(formats_dir() / k.file);
        EXPECT_EQ(c.source, "wkt");
        EXPECT_EQ(c.epsg, k.epsg);
        EXPECT_EQ(c.vertical_epsg, k.vertical_epsg);
        EXPECT_EQ(c.geographic, k.geographic);
        EXPECT_EQ(c.horizontal_unit, k.horizontal);
        EXPECT_EQ(c.vertical_unit, k.vertical);
        EXPECT_EQ(std::isnan(c.horizontal_to_metres), k.horizontal == LinearUnit::Unknown);
        EXPECT_FALSE(c.wkt.empty());
        EXPECT_TRUE(c.warnings.empty()) << joined(c.warnings);
    }
}

TEST(Crs, WktWithNestedVerticalAndContradictoryUnit) {
    // PROJCS holding a VERTCS whose unit is named "US survey foot" with factor 1.0.
    const Crs c = crs_of(formats_dir() / "PDAL__PDAL/test__data__las__test1_4.las");
    EXPECT_EQ(c.source, "wkt");
    EXPECT_EQ(c.epsg, 2903);
    EXPECT_EQ(c.horizontal_unit, LinearUnit::UsSurveyFoot);
    EXPECT_EQ(c.vertical_epsg, 5703);
    EXPECT_EQ(c.vertical_unit, LinearUnit::Metre);  // the factor wins ...
    EXPECT_EQ(c.vertical_unit_name, "US survey foot");
    EXPECT_TRUE(any_warning_contains(c, "nested")) << joined(c.warnings);
    EXPECT_TRUE(any_warning_contains(c, "factor 1.0")) << joined(c.warnings);  // ... and is flagged
}

TEST(Crs, WktAndGeoTiffTogether) {
    // WKT bit set: the WKT (Foot_US, no code) is used; the GeoTIFF keys say EPSG:32104
    // (a metre CRS) with US survey feet, and both contradictions are reported.
    const Crs c = crs_of(formats_dir() / "laspy__laspy/tests__data__file_with_both_wkt_and_geotiff_vlrs.las");
    EXPECT_EQ(c.source, "wkt");
    EXPECT_EQ(c.epsg, std::nullopt);
    EXPECT_EQ(c.horizontal_unit, LinearUnit::UsSurveyFoot);
    EXPECT_TRUE(any_warning_contains(c, "EPSG:32104")) << joined(c.warnings);
    EXPECT_TRUE(any_warning_contains(c, "is in metre")) << joined(c.warnings);
}

TEST(Crs, WktInAnEvlrIsReadEvenWhenNotLoaded) {
    // simple1_4.las: GeoTIFF keys (EPSG:4326) in VLRs and a WKT GEOGCS in an EVLR.
    auto file = io::File::open((formats_dir() / "laspy__laspy/tests__data__simple1_4.las").string());
    const Header h = read_header(file);
    const auto vlrs = read_vlrs(file, h);
    auto evlrs = read_evlrs(file, h);
    ASSERT_NE(find_vlr(evlrs, "LASF_Projection", 2112), nullptr);

    const Crs by_bit = read_crs(vlrs, evlrs, file, (h.global_encoding & kWktBit) != 0);
    EXPECT_EQ(by_bit.source, "geotiff");  // the WKT bit is not set
    EXPECT_EQ(by_bit.epsg, 4326);
    EXPECT_TRUE(by_bit.geographic);

    for (auto& e : evlrs) {  // force the payload to come from the file
        e.data.clear();
        e.data_loaded = false;
    }
    const Crs wkt = read_crs(vlrs, evlrs, file, true);
    EXPECT_EQ(wkt.source, "wkt");
    EXPECT_EQ(wkt.name, "Geographic Coordinate System");
    EXPECT_TRUE(wkt.geographic);
    EXPECT_EQ(wkt.horizontal_unit_name, "Degree");
}

TEST(Crs, FilesWithoutCrs) {
    for (const char* name : {"r-lidar__lasR/inst__extdata__nocrs.las", "laspy__laspy/tests__data__simple.laz"}) {
        SCOPED_TRACE(name);
        const Crs c = crs_of(formats_dir() / name);
        EXPECT_EQ(c.source, "none");
        EXPECT_EQ(c.epsg, std::nullopt);
        EXPECT_EQ(c.vertical_epsg, std::nullopt);
        EXPECT_EQ(c.horizontal_unit, LinearUnit::Unknown);
        EXPECT_TRUE(std::isnan(c.horizontal_to_metres));
        EXPECT_TRUE(std::isnan(c.z_to_metres()));
        EXPECT_STREQ(unit_name(c.horizontal_unit), "unknown");
        EXPECT_TRUE(c.wkt.empty());
        EXPECT_TRUE(c.warnings.empty()) << joined(c.warnings);
    }
}

TEST(Crs, EmptyWktRecordIsReportedNotGuessed) {
    const Crs c = crs_of(formats_dir() / "IGNF__ctview/data__las__classee__test_data_77050_627755_LA93_IGN69.copc.laz");
    EXPECT_EQ(c.source, "none");
    EXPECT_TRUE(any_warning_contains(c, "empty")) << joined(c.warnings);
}

TEST(Crs, GeoTiffUnitKeyContradictingTheCodeIsReported) {
    // EPSG:32128 (NAD83 / Pennsylvania North, metres) with ProjLinearUnitsGeoKey = US survey foot.
    const Crs c = crs_of(formats_dir() / "laz-rs__laz-rs/tests__data__point-version-1-point-wise.laz");
    EXPECT_EQ(c.epsg, 32128);
    EXPECT_EQ(c.horizontal_unit, LinearUnit::UsSurveyFoot);
    EXPECT_TRUE(any_warning_contains(c, "EPSG:32128 is in metre")) << joined(c.warnings);
}

TEST(Crs, UnitInferredFromCodeWhenNoUnitKey) {
    // Topography: only ProjectedCSTypeGeoKey 2949 (NAD83(CSRS) / MTM zone 7, metres).
    const Crs c = crs_of(formats_dir() / "r-lidar__lidR/inst__extdata__Topography.laz");
    EXPECT_EQ(c.epsg, 2949);
    EXPECT_EQ(c.horizontal_unit, LinearUnit::Metre);
    // 1815.laz: EPSG:6580 is not in the table, so the unit stays unknown (with a warning).
    const Crs d = crs_of(formats_dir() / "hobuinc__laz-perf/cpp__test__raw-sets__1815.laz");
    EXPECT_EQ(d.epsg, 6580);
    EXPECT_EQ(d.horizontal_unit, LinearUnit::Unknown);
    EXPECT_EQ(d.vertical_epsg, 5703);
    EXPECT_EQ(d.vertical_unit, LinearUnit::Metre);
    EXPECT_TRUE(any_warning_contains(d, "EPSG:6580")) << joined(d.warnings);
}

TEST(Crs, EpsgUnitTable) {
    EXPECT_EQ(projected_unit_of_epsg(3089), LinearUnit::UsSurveyFoot);  // NAD83 / Kentucky Single Zone (ftUS)
    EXPECT_EQ(projected_unit_of_epsg(2264), LinearUnit::UsSurveyFoot);  // NAD83 / North Carolina (ftUS)
    EXPECT_EQ(projected_unit_of_epsg(2903), LinearUnit::UsSurveyFoot);  // NAD83(HARN) / New Mexico Central (ftUS)
    EXPECT_EQ(projected_unit_of_epsg(6447), LinearUnit::UsSurveyFoot);  // NAD83(2011) / Georgia West (ftUS)
    EXPECT_EQ(projected_unit_of_epsg(2222), LinearUnit::InternationalFoot);  // NAD83 / Arizona East (ft)
    EXPECT_EQ(projected_unit_of_epsg(2994), LinearUnit::InternationalFoot);  // NAD83(HARN) / Oregon GIC Lambert (ft)
    EXPECT_EQ(projected_unit_of_epsg(2154), LinearUnit::Metre);
    EXPECT_EQ(projected_unit_of_epsg(32632), LinearUnit::Metre);
    EXPECT_EQ(projected_unit_of_epsg(32119), LinearUnit::Metre);  // NAD83 / North Carolina (metres)
    EXPECT_EQ(projected_unit_of_epsg(26947), LinearUnit::Unknown);  // not an EPSG code
    EXPECT_EQ(projected_unit_of_epsg(6580), LinearUnit::Unknown);   // metres, but not in the table
    EXPECT_EQ(vertical_unit_of_epsg(6360), LinearUnit::UsSurveyFoot);
    EXPECT_EQ(vertical_unit_of_epsg(8228), LinearUnit::InternationalFoot);
    EXPECT_EQ(vertical_unit_of_epsg(5703), LinearUnit::Metre);
    EXPECT_STREQ(unit_name(LinearUnit::Metre), "metre");
    EXPECT_STREQ(unit_name(LinearUnit::InternationalFoot), "foot");
    EXPECT_DOUBLE_EQ(unit_to_metres(LinearUnit::InternationalFoot), 0.3048);
    EXPECT_DOUBLE_EQ(unit_to_metres(LinearUnit::UsSurveyFoot), 1200.0 / 3937.0);
}

// ---- Hand-built records ------------------------------------------------------------------

Vlr projection_vlr(std::uint16_t id, std::vector<std::uint8_t> data, std::uint64_t offset = 1000) {
    Vlr v;
    v.user_id = "LASF_Projection";
    v.record_id = id;
    v.header_offset = offset;
    v.data_offset = offset + 54;
    v.data_size = data.size();
    v.data = std::move(data);
    v.data_loaded = true;
    return v;
}

std::vector<std::uint8_t> shorts(std::initializer_list<std::uint16_t> values) {
    std::vector<std::uint8_t> out;
    for (std::uint16_t v : values) {
        out.push_back(static_cast<std::uint8_t>(v & 0xff));
        out.push_back(static_cast<std::uint8_t>(v >> 8));
    }
    return out;
}

std::vector<std::uint8_t> text(const std::string& s) { return {s.begin(), s.end()}; }

TEST(Crs, MalformedGeoKeysAreIgnoredWithWarnings) {
    const io::File no_file;  // all payloads are loaded: nothing is read
    // Announces 9 keys, holds 4: ProjectedCSType 3089, ProjLinearUnitSize as a double past the
    // 1-double array, GTCitation past the ascii array, and VerticalUnits 9002.
    const auto keys = shorts({1, 1, 0, 9,                //
                              3072, 0, 1, 3089,          //
                              3077, 34736, 1, 5,         //
                              1026, 34737, 40, 0,        //
                              4099, 0, 1, 9002});
    const std::vector<Vlr> vlrs = {projection_vlr(34735, keys, 500),
                                   projection_vlr(34736, std::vector<std::uint8_t>(8, 0), 600),
                                   projection_vlr(34737, text("short|"), 700)};
    const Crs c = read_crs(vlrs, {}, no_file);
    EXPECT_EQ(c.source, "geotiff");
    EXPECT_EQ(c.epsg, 3089);
    EXPECT_EQ(c.horizontal_unit, LinearUnit::UsSurveyFoot);  // from the table: 3077 was dropped
    EXPECT_EQ(c.vertical_unit, LinearUnit::InternationalFoot);
    EXPECT_TRUE(c.name.empty());
    EXPECT_TRUE(any_warning_contains(c, "announces 9 keys")) << joined(c.warnings);
    EXPECT_TRUE(any_warning_contains(c, "GeoKey 3077 refers to doubles 5..6")) << joined(c.warnings);
    EXPECT_TRUE(any_warning_contains(c, "GeoKey 1026 refers to characters 0..40")) << joined(c.warnings);
    EXPECT_TRUE(any_warning_contains(c, "VLR at offset 500")) << joined(c.warnings);
    for (const auto& w : c.warnings) {  // levelled, and placed at the record they are about
        EXPECT_EQ(w.level, DiagnosticLevel::warning);
        EXPECT_EQ(w.offset, 500u) << w.message;
    }
}

TEST(Crs, TruncatedGeoKeysFallBackToWkt) {
    const io::File no_file;
    const std::vector<Vlr> vlrs = {
        projection_vlr(34735, {1, 0, 1}),  // 3 bytes: not even a header
        projection_vlr(2112,
                       text(R"w(PROJCS["x",UNIT["US survey foot",0.3048006096012192],AUTHORITY["EPSG","2264"]])w")),
    };
    const Crs c = read_crs(vlrs, {}, no_file);
    EXPECT_EQ(c.source, "wkt");
    EXPECT_EQ(c.epsg, 2264);
    EXPECT_EQ(c.horizontal_unit, LinearUnit::UsSurveyFoot);
    EXPECT_TRUE(any_warning_contains(c, "shorter than its 8-byte header")) << joined(c.warnings);
    EXPECT_TRUE(any_warning_contains(c, "WKT bit is not set")) << joined(c.warnings);
}

TEST(Crs, BrokenWktNeverThrows) {
    const std::string deep = std::string(5000, 'A');
    std::string nested;
    for (int i = 0; i < 10000; ++i) nested += "A[";
    for (const std::string& bad : {std::string(R"w(PROJCS["unterminated)w"), std::string("PROJCS[,]"),
                                   std::string("PROJCS"), std::string("[[[["), nested, deep,
                                   std::string(R"w(PROJCS["a",UNIT["metre","abc"]])w"),
                                   std::string(R"w(PROJCS["a",AUTHORITY["EPSG","99999999999999"]])w")}) {
        Crs c;
        ASSERT_NO_THROW(c = parse_wkt_crs(bad)) << bad.substr(0, 40);
        EXPECT_FALSE(c.warnings.empty()) << bad.substr(0, 40);
        EXPECT_EQ(c.epsg, std::nullopt);
    }
}

TEST(Crs, WktSyntaxVariants) {
    // Parentheses, blanks before brackets, an escaped quote, an unusual unit, and a BOUNDCRS.
    Crs c = parse_wkt_crs(R"w(PROJCS ("a ""b""", UNIT ("link", 0.201168), AUTHORITY ("EPSG", "1234")))w");
    EXPECT_EQ(c.source, "wkt");
    EXPECT_EQ(c.name, "a \"b\"");
    EXPECT_EQ(c.epsg, 1234);
    EXPECT_EQ(c.horizontal_unit, LinearUnit::Other);
    EXPECT_EQ(c.horizontal_unit_name, "link");
    EXPECT_DOUBLE_EQ(c.horizontal_to_metres, 0.201168);
    EXPECT_STREQ(unit_name(c.horizontal_unit), "other");

    c = parse_wkt_crs(R"w(BOUNDCRS[SOURCECRS[PROJCRS["p",CS[Cartesian,2],AXIS["e",east,LENGTHUNIT["foot",0.3048]],)w"
                      R"w(ID["EPSG",2222]]],TARGETCRS[GEOGCRS["WGS 84"]],ABRIDGEDTRANSFORMATION["t"]])w");
    EXPECT_EQ(c.epsg, 2222);
    EXPECT_EQ(c.horizontal_unit, LinearUnit::InternationalFoot);
    EXPECT_TRUE(c.warnings.empty()) << joined(c.warnings);

    c = parse_wkt_crs(
        R"w(VERT_CS["NAVD88 height (ftUS)",UNIT["US survey foot",0.304800609601219],AUTHORITY["EPSG","6360"]])w");
    EXPECT_EQ(c.epsg, std::nullopt);
    EXPECT_EQ(c.vertical_epsg, 6360);
    EXPECT_EQ(c.vertical_unit, LinearUnit::UsSurveyFoot);
    EXPECT_DOUBLE_EQ(c.vertical_to_metres, 1200.0 / 3937.0);
}

}  // namespace
}  // namespace lidarscout::las
