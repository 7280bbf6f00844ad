// MultiPolygon: points inside, outside, on edges and vertices, in holes and in the parts of a
// multipolygon; WKT and GeoJSON parsed, and their errors naming what was expected; GeoJSON nested
// 60k deep, or with a field of the wrong kind, one Error (never a crash, never a JSON library's).
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "allocation_counter.hpp"
#include "core/error.hpp"
#include "core/polygon.hpp"

namespace lidarscout {
namespace {

// The message of the Error parsing `text` ("" when it parses).
std::string error_of(const std::string& text, MultiPolygon (*parse)(std::string_view) = parse_wkt_polygon) {
    try {
        parse(text);
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

TEST(Polygon, SquareWithHoleEdgesInside) {
    const auto p = parse_wkt_polygon("POLYGON ((0 0, 10 0, 10 10, 0 10, 0 0), (4 4, 6 4, 6 6, 4 6, 4 4))");
    EXPECT_TRUE(p.contains(1, 1));
    EXPECT_TRUE(p.contains(0, 5));    // on an outer edge
    EXPECT_TRUE(p.contains(10, 10));  // a vertex
    EXPECT_TRUE(p.contains(4, 5));    // on the hole's edge
    EXPECT_FALSE(p.contains(5, 5));   // in the hole
    EXPECT_FALSE(p.contains(10.000001, 5));
    EXPECT_FALSE(p.contains(-1, 0));  // on the line of the bottom edge, outside
    EXPECT_FALSE(p.contains(11, 10)); // on the line of the top edge, outside
    EXPECT_DOUBLE_EQ(p.area(), 96.0);
}

TEST(Polygon, MultiPolygonPartsAndATriangle) {
    const auto p = parse_wkt_polygon("multipolygon Z (((0 0 1, 2 0 1, 0 2 1)), ((5 5 0, 7 5 0, 7 7 0, 5 7 0)))");
    EXPECT_TRUE(p.contains(0.5, 0.5));
    EXPECT_TRUE(p.contains(1, 1));  // on the hypotenuse
    EXPECT_FALSE(p.contains(1.01, 1.01));
    EXPECT_TRUE(p.contains(6, 6));
    EXPECT_FALSE(p.contains(3, 3));
    EXPECT_EQ(p.polygons().size(), 2u);
    EXPECT_DOUBLE_EQ(p.min_x(), 0);
    EXPECT_DOUBLE_EQ(p.max_y(), 7);
}

TEST(Polygon, TouchesBox) {
    const auto p = parse_wkt_polygon("POLYGON ((0 0, 10 0, 0 10), (1 1, 3 1, 1 3))");
    EXPECT_TRUE(p.touches_box(-5, -5, 20, 20));   // the polygon inside the box
    EXPECT_TRUE(p.touches_box(0.5, 0.5, 0.6, 0.6));  // the box inside the polygon
    EXPECT_TRUE(p.touches_box(5, 5, 8, 8));       // a corner on the hypotenuse
    EXPECT_FALSE(p.touches_box(5.1, 5.1, 8, 8));  // within the polygon's box, beyond the hypotenuse
    EXPECT_FALSE(p.touches_box(1.2, 1.2, 1.4, 1.4));  // inside the hole
    EXPECT_TRUE(p.touches_box(-1, 4, 11, 4.5));   // crossing, no vertex inside either
    EXPECT_FALSE(p.touches_box(11, 0, 12, 1));
}

TEST(Polygon, GeoJsonFeatureCollection) {
    const auto p = parse_geojson_polygon(R"({"type": "FeatureCollection", "features": [
        {"type": "Feature", "properties": {}, "geometry": {"type": "Polygon",
         "coordinates": [[[0, 0], [10, 0], [10, 10], [0, 10], [0, 0]], [[4, 4], [6, 4], [6, 6], [4, 6], [4, 4]]]}},
        {"type": "Feature", "geometry": {"type": "MultiPolygon", "coordinates": [[[[20, 0], [30, 0], [30, 10]]]]}}]})");
    EXPECT_TRUE(p.contains(1, 1));
    EXPECT_FALSE(p.contains(5, 5));
    EXPECT_TRUE(p.contains(29, 1));
    EXPECT_FALSE(p.contains(21, 9));
    EXPECT_THROW(parse_geojson_polygon(R"({"type": "Point", "coordinates": [1, 2]})"), Error);
    EXPECT_THROW(parse_geojson_polygon("{not json"), Error);
}

TEST(Polygon, WktErrorsNameWhatWasExpected) {
    EXPECT_NE(error_of("LINESTRING (0 0, 1 1)").find("expected POLYGON or MULTIPOLYGON"), std::string::npos);
    EXPECT_NE(error_of("POLYGON ((0 0, 1 0, 1 1)").find("expected ')' at character 25"), std::string::npos);
    EXPECT_NE(error_of("POLYGON ((0 0, 1 x, 1 1))").find("expected a number"), std::string::npos);
    EXPECT_NE(error_of("POLYGON ((0 0, 1 0, 0 0))").find("at least 3 distinct vertices"), std::string::npos);
    EXPECT_NE(error_of("POLYGON ((0 0, 1 0, 1 1)) junk").find("the end of the text"), std::string::npos);
    EXPECT_EQ(error_of("POLYGON((0 0,1 0,1 1))"), "");
}

std::string geojson_error(const std::string& text) { return error_of(text, parse_geojson_polygon); }

TEST(Polygon, GeoJsonNestedDeepIsOneErrorNotACrash) {
    // A FeatureCollection of FeatureCollections, 60k deep.
    std::string deep;
    for (int i = 0; i < 60'000; ++i) deep += R"({"type": "FeatureCollection", "features": [)";
    for (int i = 0; i < 60'000; ++i) deep += "]}";
    EXPECT_NE(geojson_error(deep).find("polygon: GeoJSON: arrays and objects nested more than the limit of 256 deep"),
              std::string::npos);
    const std::string coordinates = R"({"type": "Polygon", "coordinates": )" + std::string(100'000, '[') +
                                    std::string(100'000, ']') + "}";
    EXPECT_NE(geojson_error(coordinates).find("nested more than"), std::string::npos);
    // Read from a file: the file named.
    const auto file = std::filesystem::temp_directory_path() / ("lidarscout_deep_" + std::to_string(::getpid()) +
                                                                ".geojson");
    std::ofstream(file) << deep;
    try {
        read_polygon_argument(file.string());
        ADD_FAILURE() << "read";
    } catch (const Error& e) {
        EXPECT_EQ(e.file(), file.string());
        EXPECT_NE(e.cause().find("nested more than"), std::string::npos);
    }
    std::filesystem::remove(file);
}

TEST(Polygon, GeoJsonCoordinatesAreKeptAsRingsNotAsADocument) {
    std::string text = R"({"type": "Feature", "properties": {"coordinates": {"any": "thing"}}, "geometry":
                           {"coordinates": [[)";
    constexpr int kVertices = 200'000;
    for (int i = 0; i < kVertices; ++i) {
        const double a = 6.283185307179586 * i / kVertices;
        text += (i ? "," : "") + std::string("[") + std::to_string(1000 * std::cos(a)) + ", " +
                std::to_string(1000 * std::sin(a)) + ", 12.5]";
    }
    text += R"(]], "type": "Polygon"}})";  // (the type after the coordinates)
    const test::AllocationCounter counter;
    const auto p = parse_geojson_polygon(text);
    const std::size_t peak = counter.peak_bytes();
    ASSERT_EQ(p.polygons().size(), 1u);
    EXPECT_EQ(p.polygons()[0][0].size(), static_cast<std::size_t>(kVertices));
    EXPECT_TRUE(p.contains(0, 0));
    EXPECT_FALSE(p.contains(1001, 0));
    EXPECT_LT(peak, 64u * kVertices) << "a few tens of bytes a vertex (a document would hold ~230), peak " << peak;
}

TEST(Polygon, GeoJsonOfTheWrongKindIsNamed) {
    EXPECT_NE(geojson_error(R"({"type": 5, "coordinates": []})").find("GeoJSON: \"type\" is a number, not a string"),
              std::string::npos);
    EXPECT_NE(geojson_error(R"({"type": "FeatureCollection", "features": [{"type": "Feature", "geometry":
              {"type": ["Polygon"]}}]})").find("\"type\" is an array, not a string"), std::string::npos);
    EXPECT_NE(geojson_error(R"({"type": "FeatureCollection", "features": 3})").find("without a features array"),
              std::string::npos);
    for (const char* coordinates : {R"([[[0, 0], [1, "a"], [1, 1]]])", "[[[0, 0], [1], [1, 1]]]",
                                    R"([[[0, 0], {"x": 1}, [1, 1]]])", "[[[0, 0], [[1, 0]], [1, 1]]]"}) {
        EXPECT_NE(geojson_error(R"({"type": "Polygon", "coordinates": )" + std::string(coordinates) + "}")
                      .find("a position is not an array of at least two numbers"),
                  std::string::npos)
            << coordinates;
    }
    EXPECT_NE(geojson_error(R"({"type": "Polygon", "coordinates": [[0, 0], [1, 0], [1, 1]]})")
                  .find("not an array of rings"),
              std::string::npos);
    EXPECT_NE(geojson_error(R"({"type": "MultiPolygon", "coordinates": 5})").find("not an array"), std::string::npos);
    const std::string long_type = geojson_error(R"({"type": ")" + std::string(100'000, 'T') + "\"}");
    EXPECT_NE(long_type.find("... (100000 bytes)"), std::string::npos);
    EXPECT_LT(long_type.size(), 400u);
    EXPECT_NE(geojson_error("{\"type\": \"Polygon\", \"coordinates\": [[[0, 0], [1, 0], [1, 1]]]} x").find("not JSON"),
              std::string::npos);
}

}  // namespace
}  // namespace lidarscout
