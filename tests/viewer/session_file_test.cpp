// Sessions: saved and opened again unchanged (camera, filter, colour, measurements, annotations,
// profiles); fields this version does not know kept, and written back compact (a saved session's
// size follows what it holds); a newer version, a version that is not one (1e300, -5, 1.5, "1"), a
// file that is not a session (a "kind" of the wrong kind too), a field of the wrong kind, a bad
// filter and a bad profile, nesting 100k deep and a string past the reader's limit refused with
// the file named, in one line; written through a temporary name. Every number within its range
// (issue 53: a camera distance of 1e300 was an empty view): each out-of-range value refused in one line
// naming the file, the field and the range; a yaw wraps and a pitch from -90 to 90 is clamped to the
// camera's range, each with a note naming the file; a yaw is saved wrapped.
#include "viewer/session_file.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <tuple>
#include <utility>
#include <vector>

#include "core/error.hpp"
#include "temp_dir_fixture.hpp"

namespace lidarscout::viewer {
namespace {

class SessionFileTest : public test::TempDirTest {
protected:
    void write_text(const std::string& name, const std::string& text) { std::ofstream(path(name.c_str())) << text; }
    // The cause of the Error reading `name`, "" when it reads.
    std::string refusal(const std::string& name) {
        try {
            read_session(path(name.c_str()));
        } catch (const Error& e) {
            EXPECT_EQ(e.file(), path(name.c_str()));
            return e.cause();
        }
        return "";
    }
};

SessionFile example() {
    SessionFile s;
    s.paths = {"/data/tiles", "https://example.org/a.laz"};
    s.crs = "EPSG:2154";
    s.camera = CameraPose{{654321.5, 6543210.25, 120.0}, 850.0, 30.0, -45.0, 50.0};
    s.filter = PointFilter::parse("2,9", "last", "10-900");
    s.colour = "classification";
    s.measurements = {{{1, 2, 3}, {4, 5, 6.5}}};
    s.annotations = {{{654300, 6543200, 101.25}, "culvert, blocked"}, {{1, 1, 1}, "ünïcode «label»"}};
    s.profiles = {{{5208145.5, 3902993.25, 5209000.125, 3904000.0}, 6.5}, {{0, 0, 1, 1}, 2}};
    return s;
}

TEST_F(SessionFileTest, SavedAndOpenedAgainUnchanged) {
    const SessionFile s = example();
    write_session(path("a.lidarscout.json"), s);
    const SessionFile r = read_session(path("a.lidarscout.json"));
    EXPECT_EQ(r.version, kSessionVersion);
    EXPECT_EQ(r.paths, s.paths);
    EXPECT_EQ(r.crs, s.crs);
    EXPECT_EQ(r.camera, s.camera);
    EXPECT_EQ(r.filter, s.filter);
    EXPECT_EQ(r.colour, s.colour);
    EXPECT_EQ(r.measurements, s.measurements);
    EXPECT_EQ(r.annotations, s.annotations);
    EXPECT_EQ(r.profiles, s.profiles);
    // A filter keeping every kind and one keeping none both survive.
    SessionFile none = s;
    none.filter.return_kinds = 0;
    write_session(path("b.lidarscout.json"), none);
    EXPECT_EQ(read_session(path("b.lidarscout.json")).filter.return_kinds, 0);
    for (const auto& e : std::filesystem::directory_iterator(dir)) {
        EXPECT_EQ(e.path().extension(), ".json") << "a temporary file was left: " << e.path();
    }
}

TEST_F(SessionFileTest, FieldsItDoesNotKnowAreKept) {
    nlohmann::json j = session_json(example());
    j["volumes"] = {{{"polygon", {0, 0, 10, 10}}, {"depth", 2}}};  // a later version's field
    j["note"] = "from a newer build";
    write_text("future.json", j.dump());
    SessionFile s = read_session(path("future.json"));
    s.annotations.push_back({{7, 8, 9}, "added here"});
    write_session(path("again.json"), s);
    const auto back = nlohmann::json::parse(std::ifstream(path("again.json")));
    EXPECT_EQ(back.at("volumes"), j.at("volumes"));
    EXPECT_EQ(back.at("profiles"), j.at("profiles"));
    EXPECT_EQ(back.at("note"), "from a newer build");
    EXPECT_EQ(back.at("annotations").size(), 3u);
}

TEST_F(SessionFileTest, WhatIsNotASessionIsRefusedNamingTheFile) {
    write_text("text.json", "hello");
    EXPECT_NE(refusal("text.json").find("not JSON"), std::string::npos);
    write_text("other.json", R"({"type": "FeatureCollection"})");
    EXPECT_NE(refusal("other.json").find("not a lidarscout session"), std::string::npos);
    nlohmann::json newer = session_json(example());
    newer["version"] = kSessionVersion + 1;
    write_text("newer.json", newer.dump());
    EXPECT_NE(refusal("newer.json").find("newer than this program's"), std::string::npos);
    nlohmann::json wrong = session_json(example());
    wrong["camera"]["distance"] = "far";
    write_text("wrong.json", wrong.dump());
    EXPECT_EQ(refusal("wrong.json"), "camera: \"distance\" is a string, not a number");
    nlohmann::json bad_filter = session_json(example());
    bad_filter["filter"]["classes"] = "999";
    write_text("filter.json", bad_filter.dump());
    EXPECT_NE(refusal("filter.json").find("--classes expects"), std::string::npos);
    EXPECT_NE(refusal("missing.json").find("cannot open"), std::string::npos);
    nlohmann::json purple = session_json(example());
    purple["colour"] = "purple";
    write_text("purple.json", purple.dump());
    EXPECT_FALSE(refusal("purple.json").empty());
    EXPECT_EQ(refusal("newer.json").empty(), false);
    nlohmann::json short_line = session_json(example());
    short_line["profiles"][0]["line"] = {1, 2, 3};
    write_text("line.json", short_line.dump());
    EXPECT_NE(refusal("line.json").find("[x0, y0, x1, y1]"), std::string::npos);
    nlohmann::json flat = session_json(example());
    flat["profiles"][0]["width"] = 0;
    write_text("width.json", flat.dump());
    EXPECT_NE(refusal("width.json").find("width is not positive"), std::string::npos);
}

// The example session with `text` (a JSON value, as written) in place of the value at `pointer`.
std::string with_value(const std::string& pointer, const std::string& text) {
    nlohmann::json j = session_json(example());
    j[nlohmann::json::json_pointer(pointer)] = "@@";
    std::string out = j.dump();
    return out.replace(out.find("\"@@\""), 4, text);
}

TEST_F(SessionFileTest, EveryNumberOutsideItsRangeIsRefusedNamingTheFieldAndTheRange) {
    const std::string target = "camera: a number of \"target\" is ";
    const std::vector<std::pair<std::pair<std::string, std::string>, std::string>> cases = {
        {{"/camera/distance", "1e300"}, "camera: \"distance\" is 1e+300, outside the range 1 to 5e+06 (metres)"},
        {{"/camera/distance", "-5"}, "camera: \"distance\" is -5, outside the range 1 to 5e+06 (metres)"},
        {{"/camera/distance", "0"}, "camera: \"distance\" is 0, outside the range 1 to 5e+06 (metres)"},
        {{"/camera/target/0", "1e300"}, target + "1e+300, outside the range -1e+08 to 1e+08 (world metres)"},
        {{"/camera/target/2", "-2e8"}, target + "-2e+08, outside the range -1e+08 to 1e+08 (world metres)"},
        {{"/camera/pitch_deg", "120"}, "camera: \"pitch_deg\" is 120, outside the range -90 to 90 (degrees)"},
        {{"/camera/fov_deg", "0"}, "camera: \"fov_deg\" is 0, outside the range 1 to 170 (degrees)"},
        {{"/camera/fov_deg", "1e300"}, "camera: \"fov_deg\" is 1e+300, outside the range 1 to 170 (degrees)"},
        {{"/measurements/0/to/1", "1e300"},
         "measurements #1: a number of \"to\" is 1e+300, outside the range -1e+08 to 1e+08 (world metres)"},
        {{"/annotations/1/at/0", "-1e300"},
         "annotations #2: a number of \"at\" is -1e+300, outside the range -1e+08 to 1e+08 (world metres)"},
        {{"/profiles/1/line/3", "1e300"},
         "profiles #2: a number of \"line\" is 1e+300, outside the range -1e+08 to 1e+08 (CRS units)"},
        {{"/profiles/0/width", "1e300"},
         "profiles #1: \"width\" is 1e+300, outside the range 0 to 1e+06 (CRS units, more than 0)"},
        {{"/profiles/0/width", "-1"}, "profiles #1: a profile's width is not positive"},
        {{"/profiles/1/line", "[3, 4, 3, 4]"}, "profiles #2: the two ends of \"line\" are the same point"},
    };
    for (const auto& [where, expected] : cases) {
        write_text("range.json", with_value(where.first, where.second));
        EXPECT_EQ(refusal("range.json"), expected) << where.first << " = " << where.second;
    }
    // Numbers JSON cannot hold are not JSON; one past a double's range is not finite.
    write_text("nan.json", with_value("/camera/distance", "NaN"));
    EXPECT_NE(refusal("nan.json").find("not JSON"), std::string::npos) << refusal("nan.json");
    write_text("inf.json", with_value("/camera/yaw_deg", "1e400"));
    EXPECT_FALSE(refusal("inf.json").empty());
}

TEST_F(SessionFileTest, AYawWrapsAndAPitchIsClampedEachWithANote) {
    const std::vector<std::tuple<std::string, std::string, double, std::string>> cases = {
        {"/camera/yaw_deg", "370", 10.0, "\"yaw_deg\" 370 is read as 10 (the same heading, from -180 to 180)"},
        {"/camera/yaw_deg", "-190", 170.0, "\"yaw_deg\" -190 is read as 170 (the same heading, from -180 to 180)"},
        {"/camera/yaw_deg", "180", -180.0, "\"yaw_deg\" 180 is read as -180 (the same heading, from -180 to 180)"},
        {"/camera/pitch_deg", "-90", -89.5,
         "\"pitch_deg\" -90 is read as -89.5 (the camera's range is -89.5 to 10 degrees)"},
        {"/camera/pitch_deg", "45", 10.0, "\"pitch_deg\" 45 is read as 10 (the camera's range is -89.5 to 10 degrees)"},
    };
    for (const auto& [pointer, text, read, note] : cases) {
        write_text("angle.json", with_value(pointer, text));
        const SessionFile s = read_session(path("angle.json"));
        ASSERT_TRUE(s.camera);
        EXPECT_EQ(pointer == "/camera/yaw_deg" ? s.camera->yaw_deg : s.camera->pitch_deg, read) << text;
        ASSERT_EQ(s.notes.size(), 1u) << text;
        EXPECT_EQ(s.notes[0].level, DiagnosticLevel::note);
        EXPECT_EQ(s.notes[0].file, path("angle.json"));
        EXPECT_EQ(s.notes[0].message, path("angle.json") + ": camera: " + note);
    }
    write_text("far.json", with_value("/camera/yaw_deg", "1e300"));
    const double far = read_session(path("far.json")).camera->yaw_deg;
    EXPECT_TRUE(far >= -180 && far < 180) << far;
    // A yaw turned past a full turn (orbiting adds up) is saved wrapped: read again without a note.
    SessionFile turned = example();
    turned.camera->yaw_deg = 725;
    write_session(path("turned.json"), turned);
    const SessionFile again = read_session(path("turned.json"));
    EXPECT_EQ(again.camera->yaw_deg, 5.0);
    EXPECT_TRUE(again.notes.empty());
    EXPECT_TRUE(read_session(path("turned.json")).notes.empty());
}

TEST_F(SessionFileTest, OnlyAVersionThisProgramReadsIsRead) {
    for (const char* version :
         {"1e300", "-5", "1.5", "\"1\"", "0", "-1e300", "null", "[1]", "18446744073709551615.5"}) {
        nlohmann::json j = session_json(example());
        std::string text = j.dump();
        const std::string at = "\"version\":1";
        ASSERT_NE(text.find(at), std::string::npos);
        text.replace(text.find(at), at.size(), std::string("\"version\":") + version);
        write_text("v.json", text);
        const std::string cause = refusal("v.json");
        if (std::string(version) == "null") {
            EXPECT_EQ(cause, "a session without a \"version\"");
        } else {
            EXPECT_NE(cause.find("is not a supported session version"), std::string::npos) << version << ": " << cause;
        }
    }
    nlohmann::json far = session_json(example());
    far["version"] = 18446744073709551615ull;
    write_text("far.json", far.dump());
    EXPECT_NE(refusal("far.json").find("newer than this program's"), std::string::npos);
}

TEST_F(SessionFileTest, AKindOfTheWrongKindIsNotASession) {
    for (const nlohmann::json& kind : {nlohmann::json(5), nlohmann::json::array(), nlohmann::json()}) {
        nlohmann::json j = session_json(example());
        j["kind"] = kind;
        write_text("k.json", j.dump());
        EXPECT_NE(refusal("k.json").find("not a lidarscout session"), std::string::npos) << kind;
    }
    write_text("array.json", "[1, 2]");
    EXPECT_NE(refusal("array.json").find("not a lidarscout session"), std::string::npos);
    nlohmann::json paths = session_json(example());
    paths["paths"] = {"a.laz", 7};
    write_text("paths.json", paths.dump());
    EXPECT_EQ(refusal("paths.json"), "paths #2: is a number, not a string");
    nlohmann::json text = session_json(example());
    text["annotations"] = {{{"at", {1, 2, 3}}, {"text", 5}}};
    write_text("text5.json", text.dump());
    EXPECT_EQ(refusal("text5.json"), "annotations #1: \"text\" is a number, not a string");
}

TEST_F(SessionFileTest, AnUnknownFieldNestedAHundredThousandDeepIsOneLine) {
    std::string text = session_json(example()).dump();
    text.insert(1, "\"later\": " + std::string(100'000, '[') + std::string(100'000, ']') + ", ");
    write_text("deep.json", text);
    const std::string cause = refusal("deep.json");
    EXPECT_NE(cause.find("nested more than the limit of 256 deep"), std::string::npos) << cause;
    const std::string big = R"({"kind": "lidarscout session", "version": 1, "note": ")" + std::string(3u << 20, 'n') +
                            "\"}";
    write_text("big.json", big);
    const std::string long_string = refusal("big.json");
    EXPECT_NE(long_string.find("a string of 3145728 bytes"), std::string::npos);
    EXPECT_LT(long_string.size(), 200u);
}

TEST_F(SessionFileTest, SavingGrowsWithWhatTheSessionHolds) {
    // ~60 KB of a later version's fields, each nested 250 deep: indented, each would cost its depth per line.
    std::string later = "[";
    for (int i = 0; i < 120; ++i) later += (i ? "," : "") + std::string(250, '[') + "1" + std::string(250, ']');
    later += "]";
    std::string text = session_json(example()).dump();
    text.insert(1, "\"later\": " + later + ", ");
    write_text("wide.json", text);
    const SessionFile s = read_session(path("wide.json"));
    write_session(path("saved.json"), s);
    const auto in = std::filesystem::file_size(path("wide.json"));
    const auto out = std::filesystem::file_size(path("saved.json"));
    EXPECT_GT(in, 60'000u);
    EXPECT_LT(out, in + 4096) << "saved as it came (known fields indented), not " << out << " bytes";
    const SessionFile again = read_session(path("saved.json"));
    EXPECT_EQ(again.unknown.at("later"), s.unknown.at("later"));
    EXPECT_EQ(again.annotations, s.annotations);
}

}  // namespace
}  // namespace lidarscout::viewer
